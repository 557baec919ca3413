"""The AST's nodes keep their hash (symsynth/logic/ast.py): hashing a node
again does not walk its subtree, the value is a dataclass's, and a pickled
node does not carry it to a process whose string hashes differ."""

from __future__ import annotations

import pickle
import subprocess
import sys

from symsynth.logic import ast, parse_ltlf


def test_a_node_hashes_its_subtree_once():
    formula = ast.Until(ast.Atom("a"), ast.Not(ast.Atom("b")))
    first = hash(formula)
    assert first == hash((ast.Atom("a"), ast.Not(ast.Atom("b"))))  # (as a dataclass hashes)
    object.__setattr__(formula.right, "arg", ast.Atom("c"))  # (behind the frozen node's back)
    assert hash(formula) == first  # kept, not computed again from the subtree


def test_equal_formulas_hash_alike_and_a_pickle_carries_no_hash():
    text = "G(at(black, top) -> X[!] (a U b)) & F last"
    formula = parse_ltlf(text)
    assert hash(formula) == hash(parse_ltlf(text)) and formula == parse_ltlf(text)
    program = ("import pickle, sys; from symsynth.logic import parse_ltlf; "
               "f = pickle.loads(sys.stdin.buffer.read()); "
               f"print(f == parse_ltlf({text!r}) and f in {{parse_ltlf({text!r})}})")
    for seed in ("1", "2"):
        done = subprocess.run([sys.executable, "-c", program], input=pickle.dumps(formula), capture_output=True,
                              env={"PYTHONHASHSEED": seed, "PATH": "/usr/bin:/bin"}, check=True)
        assert done.stdout.strip() == b"True", done.stderr
