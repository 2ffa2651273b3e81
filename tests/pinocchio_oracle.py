"""The same chain and bodies in Pinocchio, an independent engine used only as a test oracle."""

import numpy as np
import pinocchio as pin

from inertiaproof.model.inertia import inertia_com, unpack


def pinocchio_model(chain, theta):
    """A pin.Model whose joint k moves body k with parameters theta[k] (paper order, body frame)."""
    model = pin.Model()
    model.gravity.linear = np.asarray(chain.gravity, dtype=float)
    parent, previous_after = 0, np.eye(4)
    for k, joint in enumerate(chain.joints):
        placement = previous_after @ joint.before
        axis = np.asarray(joint.axis, dtype=float)
        jm = pin.JointModelRevoluteUnaligned(axis) if joint.revolute else pin.JointModelPrismaticUnaligned(axis)
        jid = model.addJoint(parent, jm, pin.SE3(placement[:3, :3], placement[:3, 3]), f"joint{k + 1}")
        m, h, _ = unpack(theta[k])
        body = pin.Inertia(float(m), h / m, inertia_com(theta[k]))
        after = pin.SE3(joint.after[:3, :3], joint.after[:3, 3])
        model.appendBodyToJoint(jid, after.act(body), pin.SE3.Identity())
        parent, previous_after = jid, joint.after
    return model


def joint_variables(chain, q):
    """Pinocchio's joint positions: the coordinate maps applied to q."""
    return np.array([j.coordinate.value(x) for j, x in zip(chain.joints, q)])
