"""Pinocchio's own URDF reader as the oracle for chains extracted from a URDF."""

import numpy as np
import pinocchio as pin
from lxml import etree


def chain_only_xml(path, tree, serial_chain):
    """The URDF text with only the links of the chain's base and bodies, and the joints between them."""
    root = etree.parse(str(path)).getroot()
    keep = set(tree.groups[serial_chain.base].links) | {name for body in serial_chain.bodies for name in body.links}
    for element in list(root):
        if element.tag == "link" and element.get("name") in keep:
            continue
        if element.tag == "joint" and {element.find("parent").get("link"), element.find("child").get("link")} <= keep:
            continue
        root.remove(element)
    return etree.tostring(root).decode()


def crba(model, joint_names, q):
    """Pinocchio's mass matrix at coordinates ``q`` of the named joints (others at neutral), in that order."""
    data = model.createData()
    config = pin.neutral(model)
    for name, x in zip(joint_names, q):
        jid = model.getJointId(name)
        i = model.idx_qs[jid]
        if model.nqs[jid] == 2:  # continuous joints: (cos, sin)
            config[i:i + 2] = np.cos(x), np.sin(x)
        else:
            config[i] = x
    m = pin.crba(model, data, config)
    m = np.triu(m) + np.triu(m, 1).T
    v = [model.idx_vs[model.getJointId(name)] for name in joint_names]
    return m[np.ix_(v, v)]
