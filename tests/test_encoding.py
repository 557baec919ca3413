"""The bit-vector encoding of the abstract state against a brute-force
enumeration of semantics §2's well-formed states and §3's propositions."""


import pytest

from symsynth.automata.bdd import new_manager
from symsynth.scene.propositions import Proposition
from symsynth.scene import scene_from_data
from symsynth.solvers.bdd.encoding import StateEncoding
from support.games import well_formed_states

SCENES = [
    ({"a": {"at": "l1"}, "b": {"at": "Else"}, "c": {}}, ["l1", "l2", "l3"], ["top", "side"]),
    ({"a": {}}, ["l1"], ["top"]),
    ({"w1": {"tags": ["white"]}, "w2": {"tags": ["white"]}, "k": {"tags": ["black"]}, "d": {}},
     ["l1", "l2", "l3", "l4", "l5"], ["g"]),
]


def prop_holds(scene, prop, at):
    if prop.kind == "occupied":
        return prop.location in at.values()
    if prop.kind == "free":
        return prop.location not in at.values()
    where = "Hand" if prop.kind == "holding" else prop.location
    return any(at[o] == where for o in scene.tagged(prop.tag))


@pytest.mark.parametrize("objects,locations,grasps", SCENES)
def test_well_formed_states_are_exactly_the_spec_states(objects, locations, grasps):
    scene = scene_from_data({"name": "t", "objects": objects, "locations": locations, "grasps": grasps})
    bdd = new_manager()
    enc = StateEncoding.declare(bdd, scene)
    bits = [b for d in enc.domains for b in d.bits]
    states = list(well_formed_states(scene))
    assert bdd.count(enc.well_formed(), nvars=len(bits)) == len(states)
    union = bdd.false
    for at, grip, ee in states:
        union |= enc.state(at, grip, ee)
    assert union == enc.well_formed()


def test_propositions_match_their_definition():
    objects, locations, grasps = SCENES[2]
    scene = scene_from_data({"name": "t", "objects": objects, "locations": locations, "grasps": grasps})
    bdd = new_manager()
    enc = StateEncoding.declare(bdd, scene)
    props = ([Proposition("at", t, l) for t in ("white", "black", "d") for l in locations + ["Else"]]
             + [Proposition("holding", t, None) for t in ("white", "black")]
             + [Proposition(k, None, l) for k in ("occupied", "free") for l in locations])
    predicates = {p: enc.proposition(p) for p in props}
    for at, grip, ee in well_formed_states(scene):
        cube = enc.state(at, grip, ee)
        for prop, pred in predicates.items():
            assert ((cube & pred) != bdd.false) == prop_holds(scene, prop, at), (prop, at)
