"""The prover's one memo (inertiaproof.bounds.memo): keyed by the content of everything a value depends on, so
changing any input of a chain (its axes included) is a miss, and the same content is a hit."""

import copy

import numpy as np
import pytest

from inertiaproof.bounds import memo
from inertiaproof.bounds.perron import fourier_perron_bound
from inertiaproof.dynamics.chain import Chain
from inertiaproof.scene import robots


def _mutations():
    """(what changed, the chain's data changed in it): each input of a chain."""
    base = robots.spatial_3r().chain.to_data()

    def changed(edit):
        data = copy.deepcopy(base)
        edit(data["joints"])
        return data

    def tilt(joints):
        joints[1]["axis"] = [0.0, 0.6, 0.8]

    def before(joints):
        joints[1]["before"][0][3] += 0.125

    def after(joints):
        joints[2]["after"][1][3] -= 0.25

    def limits(joints):
        joints[2]["limits"] = [-1.0, 1.5]

    def kind(joints):
        joints[2]["kind"], joints[2]["limits"] = "prismatic", [0.0, 0.5]

    return base, {"axis": changed(tilt), "fixed transform before": changed(before),
                  "fixed transform after": changed(after), "limits": changed(limits), "kind": changed(kind)}


BASE, MUTATIONS = _mutations()


@pytest.mark.parametrize("what", sorted(MUTATIONS))
def test_a_changed_input_of_the_chain_is_a_miss(what):
    chain, other = Chain.from_data(BASE), Chain.from_data(MUTATIONS[what])
    thetas = np.tile(np.array([1.0, 0, 0, 0, 0.1, 0.1, 0.1, 0, 0, 0]), (1, chain.bodies, 1))
    memo.clear("perron")
    fourier_perron_bound(chain, thetas)
    assert memo.size("perron") == 1
    fourier_perron_bound(Chain.from_data(copy.deepcopy(BASE)), thetas.copy())  # the same content: a hit
    assert memo.size("perron") == 1
    fourier_perron_bound(other, thetas)  # another chain: a miss, computed for it
    assert memo.size("perron") == 2, what
    assert memo.key_of(chain, thetas) != memo.key_of(other, thetas)


def test_the_coordinate_map_and_every_other_input_are_in_the_key():
    chain = Chain.from_data(BASE)
    data = copy.deepcopy(BASE)
    data["joints"][1]["coordinate"] = "cubic"
    assert memo.key_of(chain) != memo.key_of(Chain.from_data(data))
    a = np.ones((1, 3, 10))
    assert memo.key_of(chain, a) == memo.key_of(chain, a.copy())
    assert memo.key_of(chain, a) != memo.key_of(chain, a.reshape(3, 1, 10))  # the shape counts, not only the bytes
    assert memo.key_of(chain, a, 20) != memo.key_of(chain, a, 800)  # the budget counts


def test_the_memo_keeps_its_last_keys_per_kind():
    calls = []
    chain = Chain.from_data(BASE)
    memo.clear("test")
    for k in range(memo.SIZE + 3):
        memo.memo("test", chain, (k,), lambda k=k: calls.append(k) or k)
    assert memo.size("test") == memo.SIZE
    assert memo.memo("test", chain, (memo.SIZE + 2,), lambda: calls.append("again")) == memo.SIZE + 2
    memo.memo("test", chain, (0,), lambda: calls.append("evicted"))
    assert calls[-1] == "evicted" and "again" not in calls
    memo.clear("test")
