"""Hostile XML in robot files: DTD entities (issue 27).

Internal entities are expanded in both readers (URDF: lxml; MJCF: in place, for MuJoCo, whose parser does not
expand them) and the audit is then the audit of the same file written without them, positions included.
What cannot be expanded safely (external entities, parameter entities, undeclared ones, loops, deep nesting,
markup, expansion bombs) is refused with one line naming the file, fast, and without reading anything else.
"""

import json
import re
import resource
import time

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from inertiaproof import cli
from inertiaproof.audit.document import audit_paths
from inertiaproof.audit.entities import GROWTH, MAX_DEPTH

mujoco = pytest.importorskip("mujoco", reason="MJCF reading needs the mujoco package (inertiaproof[mjcf])")

URDF = """<?xml version="1.0"?>
<robot name="arm">
  <link name="base"/>
  <link name="l1">
    <inertial><origin xyz="0.1 0 0.05" rpy="0.3 0.2 0.1"/><mass value="1.25"/>
      <inertia ixx="0.01" iyy="0.02" izz="0.025" ixy="0" iyz="0" ixz="0"/></inertial>
  </link>
  <link name="l2">
    <inertial><origin xyz="0.2 0 0" rpy="0 0 0"/><mass value="0.05"/>
      <inertia ixx="0.001" iyy="0.001" izz="0.01" ixy="0" iyz="0" ixz="0"/></inertial>
  </link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><origin xyz="0 0 0.1"/>
    <axis xyz="0 0 1"/><limit lower="-1.5" upper="1.5" effort="1" velocity="1"/></joint>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/><origin xyz="0.3 0 0.05" rpy="0.5 0 0.2"/>
    <axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>
"""

MJCF = """<mujoco model="m">
  <worldbody>
    <body name="l1" pos="0 0 0.1">
      <joint name="j1" type="hinge" axis="0 0 1" range="-1.5 1.5"/>
      <inertial pos="0.01 0.02 0.03" mass="0.7" diaginertia="0.01 0.02 0.025"/>
      <body name="l2" pos="0.3 0 0">
        <joint name="j2" type="hinge" axis="0 1 0" range="-1 1"/>
        <inertial pos="0 0 0" mass="0.5" fullinertia="0.01 0.01 0.03 0.002 -0.001 0.0005"/>
      </body>
    </body>
  </worldbody>
</mujoco>
"""

FORMATS = {"urdf": (URDF, "robot", "robot.urdf", "<inertia "), "mjcf": (MJCF, "mujoco", "model.xml", "<inertial ")}
ATTRIBUTE = re.compile(r'(\s[\w:]+=")([^"]*)(")')
SECRET = "SECRET-MARKER-b7e1"


def with_doctype(text, root, declarations):
    """The text with a document type declaration (after the XML declaration, if any) of its own line."""
    dtd = f"<!DOCTYPE {root} [\n{declarations}\n]>\n"
    if text.startswith("<?xml"):
        head, rest = text.split("\n", 1)
        return f"{head}\n{dtd}{rest}"
    return dtd + text


def audit(path):
    return audit_paths([path], samples=64, rounds=0, bounds="none")[str(path)]


def same_audit(plain, expanded):
    """The two entries agree on everything but the file's name and the lines the DOCTYPE added."""
    a, b = json.dumps(plain, sort_keys=True), json.dumps(expanded, sort_keys=True)
    strip = re.compile(r'"(startLine|endLine|startColumn|endColumn|start|end|path)": [^,}]*')
    assert strip.sub("", a) == strip.sub("", b)


def check_positions(entry, text, opening):
    """Every located inertia element starts at its line and column in the file's text."""
    lines = text.split("\n")
    located = 0
    for name, link in entry["links"].items():
        where = link["location"]
        if where is None or link["source"] not in ("urdf", "diaginertia", "fullinertia"):
            continue
        line = lines[where["startLine"] - 1]
        assert line[where["startColumn"] - 1:].startswith(opening.strip()), (name, where, line)
        located += 1
    assert located >= 2


# -- expanded: the audit of the same file without entities ----------------------------------------------------

TRICKS = {
    "link name": ('<!ENTITY nm "l1">', [('<link name="l1">', '<link name="&nm;">'),
                                       ('<child link="l1"/>', '<child link="&nm;"/>'),
                                       ('<parent link="l1"/>', '<parent link="&nm;"/>'),
                                       ('body name="l1"', 'body name="&nm;"')]),
    "joint name": ('<!ENTITY jn "j2">', [('joint name="j2"', 'joint name="&jn;"')]),
    "mass": ('<!ENTITY m "0.05"><!ENTITY half "0.5">', [('<mass value="0.05"/>', '<mass value="&m;"/>'),
                                                        ('mass="0.5"', 'mass="&half;"')]),
    "number in inertia": ('<!ENTITY i "0.01">', [('izz="0.01"', 'izz="&i;"'),
                                                 ('fullinertia="0.01 0.01', 'fullinertia="&i; &i;')]),
    "number in a vector": ('<!ENTITY x "0.3">', [('xyz="0.3 0 0.05"', 'xyz="&x; 0 0.05"'),
                                                 ('pos="0.3 0 0"', 'pos="&x; 0 0"')]),
    "nested": ('<!ENTITY zero "0">\n<!ENTITY dot "&zero;.">\n<!ENTITY tenth "&dot;1">',
               [('iyy="0.001"', 'iyy="&dot;&zero;&zero;1"'), ('upper="1.5"', 'upper="1.5&zero;"'),
                ('diaginertia="0.01 0.02', 'diaginertia="&dot;&zero;1 0.02'), ('pos="0 0 0.1"', 'pos="0 0 &tenth;"')]),
    "predefined and character references": ('<!ENTITY q "&#48;.25">',
                                            [('<mass value="1.25"/>', '<mass value="1&#46;25"/>'),
                                             ('mass="0.7"', 'mass="&#x30;.7"')]),
}


@pytest.mark.parametrize("fmt", FORMATS)
@pytest.mark.parametrize("trick", TRICKS)
def test_internal_entities_audit_like_the_file_without_them(tmp_path, fmt, trick):
    text, root, name, opening = FORMATS[fmt]
    declarations, replacements = TRICKS[trick]
    hostile = text
    for old, new in replacements:
        hostile = hostile.replace(old, new)
    assert hostile != text or trick == "joint name" and fmt == "mjcf"
    hostile = with_doctype(hostile, root, declarations)
    (tmp_path / "plain").mkdir()
    (tmp_path / "entities").mkdir()
    (tmp_path / "plain" / name).write_text(text)
    (tmp_path / "entities" / name).write_text(hostile)
    plain, expanded = audit(tmp_path / "plain" / name), audit(tmp_path / "entities" / name)
    assert plain["status"] == expanded["status"] == "ok", expanded.get("error")
    assert not plain["consistent"] and plain["not_consistent"]  # l2 is not consistent: a repair is located
    same_audit(plain, expanded)
    check_positions(expanded, hostile, opening)


def test_the_reported_issue_link_name_and_mass(tmp_path, capsys):
    text = with_doctype(URDF.replace('<parent link="base"/>', '<parent link="&nm;"/>')
                        .replace('<mass value="1.25"/>', '<mass value="&m;"/>'), "robot",
                        '<!ENTITY nm "base"><!ENTITY m "1.25">')
    path = tmp_path / "robot.urdf"
    path.write_text(text)
    code = cli.main(["audit", "--bounds", "none", "--json", str(path)])
    out, err = capsys.readouterr()
    doc = json.loads(out)
    f = doc["files"][str(path)]
    assert code == 1 and f["status"] == "ok" and "Traceback" not in err
    assert f["links"]["l1"]["inertial"]["mass"] == 1.25 and "l2" in f["not_consistent"]
    assert f["links"]["l1"]["verdict"] == "consistent" and f["links"]["base"]["role"] == "base"


def test_mujoco_line_numbers_are_the_files(tmp_path):
    text = with_doctype(MJCF.replace('mass="0.5"', 'mass="&bad;"'), "mujoco", '<!ENTITY bad "heavy">')
    path = tmp_path / "model.xml"
    path.write_text(text)
    line = next(k for k, row in enumerate(text.split("\n"), start=1) if "&bad;" in row)
    entry = audit(path)
    assert entry["status"] == "error" and entry["error"].startswith(str(path))
    assert f"line {line}" in entry["error"] and "\n" not in entry["error"]


def test_mjcf_includes_with_entities_and_relative_files(tmp_path):
    (tmp_path / "parts").mkdir()
    (tmp_path / "parts" / "arm.xml").write_text(with_doctype(
        '<mujocoinclude><body name="l3" pos="0 0 &h;"><joint name="j3" type="slide" axis="1 0 0" range="0 1"/>'
        '<geom type="box" size=".05 .05 .05"/></body></mujocoinclude>', "mujocoinclude", '<!ENTITY h "0.2">'))
    text = with_doctype(MJCF.replace("</body>\n    </body>", '</body>\n<include file="parts/arm.xml"/>\n    </body>', 1)
                        .replace('mass="0.7"', 'mass="&m;"'), "mujoco", '<!ENTITY m "0.7">')
    path = tmp_path / "model.xml"
    path.write_text(text)
    entry = audit(path)
    assert entry["status"] == "ok", entry.get("error")
    assert entry["links"]["l1"]["inertial"]["mass"] == 0.7 and entry["links"]["l3"]["source"] == "geoms"


# -- refused: one line naming the file ------------------------------------------------------------------------

def billion_laughs(levels=10):
    out = ['<!ENTITY lol0 "lol">']
    out += [f'<!ENTITY lol{i} "{("&lol%d;" % (i - 1)) * 10}">' for i in range(1, levels)]
    return "\n".join(out), f"&lol{levels - 1};"


def refused_cases(tmp_path):
    secret = tmp_path / "secret.txt"
    secret.write_text(SECRET + "\n")
    laughs, lol = billion_laughs()
    deep = "\n".join(['<!ENTITY d0 "1">'] + [f'<!ENTITY d{i} "&d{i - 1};">' for i in range(1, MAX_DEPTH + 3)])
    big = "9" * 50_000
    return {
        "billion laughs": (laughs, [('name="l1"', f'name="{lol}"')], "expand to more than"),
        "billion laughs in content": (laughs, [("<worldbody>", f"<worldbody>{lol}"), ("<link name=\"base\"/>",
                                                                                        f"<link name=\"base\"/>{lol}")],
                                      "expand to more than"),
        "quadratic blowup": (f'<!ENTITY big "{big}">', [('mass="0.7"', 'mass="' + "&big;" * 2000 + '"'),
                                                        ('<mass value="1.25"/>',
                                                         '<mass value="' + "&big;" * 2000 + '"/>')],
                             "expand to more than"),
        "external SYSTEM /etc/passwd": ('<!ENTITY x SYSTEM "file:///etc/passwd">',
                                        [('name="l1"', 'name="&x;"')], "external entity 'x'"),
        "external SYSTEM in content": (f'<!ENTITY x SYSTEM "{secret.as_uri()}">',
                                       [("<worldbody>", "<worldbody>&x;"), ("<link name=\"base\"/>",
                                                                              "<link name=\"base\"/>&x;")],
                                       "external entity 'x'"),
        "external SYSTEM relative": ('<!ENTITY x SYSTEM "secret.txt">', [('name="l1"', 'name="&x;"')],
                                     "external entity 'x'"),
        "external PUBLIC over the network": ('<!ENTITY x PUBLIC "-//X//Y" "http://127.0.0.1:9/x.ent">',
                                             [('name="l1"', 'name="&x;"')], "external entity 'x'"),
        "parameter entity": ('<!ENTITY % p "<!ENTITY nm \'l1\'>"> %p;', [('name="l1"', 'name="&nm;"')],
                             "parameter entity '%p'"),
        "external parameter entity": ('<!ENTITY % p SYSTEM "file:///etc/passwd"> %p;', [], "parameter entity '%p'"),
        "self reference": ('<!ENTITY a "&b;"><!ENTITY b "x&a;">', [('name="l1"', 'name="&a;"')], "refers to itself"),
        "deep nesting": (deep, [('name="l1"', f'name="&d{MAX_DEPTH + 2};"')], "nest more than"),
        "markup": ('<!ENTITY extra "<link name=\'ghost\'/>">', [("<worldbody>", "<worldbody>&extra;"),
                                                               ("<link name=\"base\"/>",
                                                                "<link name=\"base\"/>&extra;")],
                   "stands for markup"),
        "undeclared": ('<!ENTITY m "1">', [('name="l1"', 'name="&nm;"')], "'&nm;' is not declared"),
    }


REFUSED = ["billion laughs", "billion laughs in content", "quadratic blowup", "external SYSTEM /etc/passwd",
           "external SYSTEM in content", "external SYSTEM relative", "external PUBLIC over the network",
           "parameter entity", "external parameter entity", "self reference", "deep nesting", "markup", "undeclared"]


@pytest.mark.parametrize("fmt", FORMATS)
@pytest.mark.parametrize("case", REFUSED)
def test_what_cannot_be_expanded_safely_is_one_line_naming_the_file(tmp_path, fmt, case):
    declarations, replacements, why = refused_cases(tmp_path)[case]
    text, root, name, _ = FORMATS[fmt]
    for old, new in replacements:
        text = text.replace(old, new)
    path = tmp_path / name
    path.write_text(with_doctype(text, root, declarations))
    before, start = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss, time.perf_counter()
    entry = audit(path)
    seconds = time.perf_counter() - start
    grown_mb = (resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before) / 1024
    assert entry["status"] == "error", entry
    error = entry["error"]
    assert error.startswith(f"{path}: ") and "\n" not in error and why in error, error
    assert seconds < 2.0 and grown_mb < 100
    assert "root:" not in error and SECRET not in error


def test_an_external_dtd_is_not_read_and_its_entities_are_refused(tmp_path):
    (tmp_path / "robot.dtd").write_text(f'<!ENTITY nm "{SECRET}">')
    path = tmp_path / "robot.urdf"
    path.write_text(with_doctype(URDF, "robot", "").replace("[\n\n]>", 'SYSTEM "robot.dtd">')
                    .replace('<link name="l1">', '<link name="&nm;">'))
    entry = audit(path)
    assert entry["status"] == "error" and "'&nm;' is not declared in the file" in entry["error"]
    assert SECRET not in json.dumps(entry)


def test_the_command_says_one_line_per_refused_file_and_audits_the_rest(tmp_path, capsys):
    laughs, lol = billion_laughs()
    (tmp_path / "good.urdf").write_text(URDF)
    (tmp_path / "bomb.urdf").write_text(with_doctype(URDF.replace('name="l1"', f'name="{lol}"'), "robot", laughs))
    (tmp_path / "passwd.urdf").write_text(with_doctype(URDF.replace('name="l1"', 'name="&x;"'), "robot",
                                                       '<!ENTITY x SYSTEM "file:///etc/passwd">'))
    start = time.perf_counter()
    code = cli.main(["audit", "--bounds", "none", str(tmp_path)])
    out, err = capsys.readouterr()
    assert time.perf_counter() - start < 10
    assert code == 2 and "Traceback" not in err and "root:" not in out + err
    errors = [line for line in err.splitlines() if line.startswith("inertiaproof: error:")]
    assert len(errors) == 2 and all(str(tmp_path) in line for line in errors)
    assert "good.urdf: robot 'arm'" in out


# -- fuzz: entities anywhere a value is, and hostile declarations mixed in -------------------------------------

@st.composite
def entity_rewrites(draw, text):
    """The text with some attribute values (or one number in them) written through entities, nested 0 to 3 deep,
    and the declarations."""
    spots = [m for m in ATTRIBUTE.finditer(text) if m.start() > text.find("?>")]  # not the XML declaration's
    chosen = draw(st.lists(st.sampled_from(range(len(spots))), min_size=1, max_size=6, unique=True))
    names = draw(st.lists(st.from_regex(r"[A-Za-z_][A-Za-z0-9_.-]{0,6}", fullmatch=True)
                          .filter(lambda n: n not in ("lt", "gt", "amp", "quot", "apos")),
                          min_size=len(chosen), max_size=len(chosen), unique=True))
    declarations, out, at = [], [], 0
    for spot, name in sorted(zip(chosen, names)):
        m = spots[spot]
        value = m.group(2)
        parts = value.split(" ")
        which = draw(st.integers(0, len(parts) - 1)) if len(parts) > 1 and draw(st.booleans()) else None
        inner = value if which is None else parts[which]
        depth = draw(st.integers(0, 3))
        chain = [f"{name}_{d}" for d in range(depth)] + [name]
        declarations.append(f'<!ENTITY {chain[0]} "{inner}">')
        for previous, current in zip(chain, chain[1:]):
            declarations.append(f'<!ENTITY {current} "&{previous};">')
        ref = f"&{name};"
        new = ref if which is None else " ".join(ref if i == which else p for i, p in enumerate(parts))
        out += [text[at:m.start(2)], new]
        at = m.end(2)
    out.append(text[at:])
    return "".join(out), "\n".join(declarations)


@pytest.mark.parametrize("fmt", FORMATS)
@settings(max_examples=15, deadline=None)
@given(data=st.data())
def test_fuzz_entities_anywhere_audit_like_the_plain_file(tmp_path_factory, fmt, data):
    text, root, name, opening = FORMATS[fmt]
    hostile, declarations = data.draw(entity_rewrites(text))
    folder = tmp_path_factory.mktemp("fuzz")
    (folder / "plain").mkdir()
    (folder / "entities").mkdir()
    (folder / "plain" / name).write_text(text)
    (folder / "entities" / name).write_text(with_doctype(hostile, root, declarations))
    plain, expanded = audit(folder / "plain" / name), audit(folder / "entities" / name)
    assert expanded["status"] == "ok", expanded.get("error")
    same_audit(plain, expanded)
    check_positions(expanded, (folder / "entities" / name).read_text(), opening)


HOSTILE_DECLARATIONS = (
    '<!ENTITY x SYSTEM "file:///etc/passwd">', '<!ENTITY % p "<!ENTITY q \'1\'>"> %p;',
    '<!ENTITY a "&a;">', '<!ENTITY m "<link name=\'z\'/>">', '<!ENTITY v "0.5">', '<!ENTITY w "&v;">',
    billion_laughs(6)[0], '<!ENTITY u PUBLIC "-//A//B" "http://127.0.0.1:9/u">', '<!-- ]> -->', '<?pi ]>?>',
    '<!ENTITY s \'quote"inside\'>', '<!ENTITY e "">', '<!ATTLIST link name CDATA "&v;">', '<!ELEMENT robot ANY>',
)
REFERENCES = ("&x;", "&q;", "&a;", "&m;", "&v;", "&w;", "&lol5;", "&u;", "&s;", "&e;", "&undeclared;", "&amp;",
              "&#48;", "&#x41;", "&v", "&;", "&&v;;")


@pytest.mark.parametrize("fmt", FORMATS)
@settings(max_examples=40, deadline=None)
@given(data=st.data())
def test_fuzz_hostile_declarations_never_crash_or_leak(tmp_path_factory, fmt, data):
    text, root, name, _ = FORMATS[fmt]
    declarations = data.draw(st.lists(st.sampled_from(HOSTILE_DECLARATIONS), max_size=5))
    spots = [m for m in ATTRIBUTE.finditer(text) if m.start() > text.find("?>")]
    chosen = data.draw(st.lists(st.tuples(st.sampled_from(range(len(spots))), st.sampled_from(REFERENCES)),
                                max_size=4, unique_by=lambda c: c[0]))
    out, at = [], 0
    for spot, ref in sorted(chosen):
        m = spots[spot]
        out += [text[at:m.start(2)], m.group(2) + ref]
        at = m.end(2)
    out.append(text[at:])
    path = tmp_path_factory.mktemp("hostile") / name
    path.write_text(with_doctype("".join(out), root, "\n".join(declarations)))
    start = time.perf_counter()
    entry = audit(path)  # never raises
    assert time.perf_counter() - start < 5
    assert "root:x:0" not in json.dumps(entry)
    if entry["status"] == "error":
        assert entry["error"].startswith(f"{path}: ") and "\n" not in entry["error"], entry["error"]


def test_limits_are_what_the_module_says():
    assert GROWTH >= 2 and MAX_DEPTH >= 4
