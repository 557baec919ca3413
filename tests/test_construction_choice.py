"""`compile_ltlf(construction="auto")`: the rule of symsynth/automata/choice.py
and progression's budget choose the construction as docs/ltlf.md says, and
the DFA is the minimal one either way (checked against the reference DFA of
tests/support/reference.py).  Which construction ran is seen by counting the
compositional construction's calls; nothing is timed."""

from __future__ import annotations

import pytest

from support.reference import distinguishing_trace, minimal_num_states, reference_dfa
from symsynth.automata import choice, compile_ltlf, compiler, compose
from symsynth.logic import atoms, parse_ltlf


@pytest.fixture
def composed(monkeypatch):
    """How many times the compositional construction ran."""
    calls = []
    original = compose.Composer.compose

    def counted(self, formula):
        calls.append(formula)
        return original(self, formula)

    monkeypatch.setattr(compose.Composer, "compose", counted)
    return calls


def check(text: str) -> None:
    formula = parse_ltlf(text)
    dfa = compile_ltlf(formula)
    assert dfa.num_states == minimal_num_states(formula), text
    assert distinguishing_trace(dfa, reference_dfa(formula), [a.key for a in atoms(formula)]) is None, text


@pytest.mark.parametrize(("text", "why"), [
    ("G(a <-> X b)", "next"),                 # the counters' counter_i <-> X carry_i
    ("G(X[!] b <-> a) & F c", "next"),
    ("G a & F b & F c", "disjoint"),          # GFand
    ("(a U b) & (c U d)", "disjoint"),        # Uconj
    ("G(a -> X b) | F c", "disjoint"),
    # assume-guarantee with two pairs plus a guarantee (bench/ltlf_generated.py's AG): 8 parts sharing atoms
    ("(G(r1 -> F !r1) & G(r2 -> F !r2) & F r1) -> (G(r1 -> F g1) & G(r2 -> F g2) & G !(g1 & g2) & F g1 & F g2)",
     "parts"),
])
def test_the_rule_sends_these_shapes_to_the_compositional_construction(text, why, composed):
    reason = choice.rule(parse_ltlf(text))
    assert reason is not None and {"next": "next", "disjoint": "disjoint", "parts": "8 temporal parts"}[why] in reason, \
        reason
    check(text)
    assert composed, text


@pytest.mark.parametrize("text", [
    "a & (G(a -> X b) -> G(b -> X a) & F(a & b))",   # chomp's shape, one connected part
    "G(a -> F b) & G(b -> F c) & G(c -> F d) & G(d -> F a) & F(a & c) & F(b & d) & G !(a & b)",  # 7 parts
    "G(a <-> b) & F(a & X b)",                         # an equivalence, no next in it
    "G(a -> X(a <-> b))",                              # a next on both sides of nothing: inside X
    "F last & G a",                                    # a part without atoms joins no group
])
def test_other_formulas_are_progressed_whole_within_the_budget(text, composed):
    assert choice.rule(parse_ltlf(text)) is None, text
    check(text)
    assert not composed, text


def test_past_the_edge_budget_the_compositional_construction_runs(monkeypatch, composed):
    text = "a & (G(a -> X b) -> G(b -> X a) & F(a & b))"
    monkeypatch.setattr(choice, "AUTO_EDGES", 3)
    check(text)
    assert composed


def test_dense_first_states_send_it_to_the_compositional_construction(monkeypatch, composed):
    """The states of G((a -> X c) & (b -> X d)) have 4 or 5 successors
    (one per set of pending c, d, and the sink once one is pending): over a
    budget of 3 per state, within one of 5."""
    text = "G((a -> X[!] c) & (b -> X[!] d))"
    monkeypatch.setattr(choice, "AUTO_DENSE_AFTER", 3)
    monkeypatch.setattr(choice, "AUTO_DEGREE", 3)
    check(text)
    assert composed
    composed.clear()
    monkeypatch.setattr(choice, "AUTO_DEGREE", 5)
    check(text)
    assert not composed


def test_dense_first_states_are_found_as_soon_as_their_edges_pass_the_budget(monkeypatch):
    """Five pending obligations: 32 states, the first with 32 successors.
    Within 16 states of 2 successors on average (32 edges), the first two
    states' edges are past the budget: the work stops there, not at the
    16th state (the verdict is the same, the count only grows)."""
    from symsynth.automata.normal import nnf
    from symsynth.automata.progression import Progression, TooDense
    formula = parse_ltlf(" & ".join(f"G(p{i} -> X[!] q{i})" for i in range(5)))
    progression = Progression([a.key for a in atoms(formula)])
    expanded = []
    original = progression._successors
    monkeypatch.setattr(progression, "_successors", lambda state, *rest: expanded.append(state) or
                        original(state, *rest))
    assert progression.dfa(nnf(formula)).num_states > 16
    expanded.clear()
    with pytest.raises(TooDense):
        progression.dfa(nnf(formula), None, (16, 2))
    assert len(expanded) == 2


def test_a_state_past_the_budget_alone_is_found_before_its_guards_are_made(monkeypatch):
    """The same DFA within 16 states of 1 successor on average: the first
    state's 32 successors are past the budget (16) and more than 16, so
    the 16th state would fail the check: it stops before any guard."""
    from symsynth.automata import progression
    from symsynth.automata.normal import nnf
    formula = parse_ltlf(" & ".join(f"G(p{i} -> X[!] q{i})" for i in range(5)))
    splits = []
    original = progression.split_letters
    monkeypatch.setattr(progression, "split_letters", lambda *args: splits.append(args) or original(*args))
    with pytest.raises(progression.TooDense):
        progression.Progression([a.key for a in atoms(formula)]).dfa(nnf(formula), None, (16, 1))
    assert splits == []


def test_limits_and_the_named_constructions_are_kept(composed):
    text = "a & (G(a -> X b) -> G(b -> X a) & F(a & b))"
    compile_ltlf(text, construction="progression")
    assert not composed
    compile_ltlf(text, construction="compositional")
    assert len(composed) == 1
    compile_ltlf(text, limits={"single": 10**9})  # limits are the compositional construction's
    assert len(composed) == 2


@pytest.fixture
def went_backward(monkeypatch):
    """The formulas the backward construction built."""
    calls = []
    original = compiler.backward_dfa

    def counted(progression, formula, *args, **kwargs):
        calls.append(formula)
        return original(progression, formula, *args, **kwargs)

    monkeypatch.setattr(compiler, "backward_dfa", counted)
    return calls


@pytest.mark.parametrize(("text", "count"), [
    ("p1 U (p2 R (p3 U p4))", 3),
    ("a U (b U c)", 1),                 # one kind: no alternation
    ("G F a", 2),
    ("!(a U !(b U c))", 2),            # NNF: !a R (b U c)
    ("G(a -> F b) & (c U (d R e))", 2),  # the longest path counts, not the sum
    ("X[!] (a U X (b R c))", 2),       # nexts are skipped
])
def test_alternation_counts_the_longest_alternating_path(text, count):
    from symsynth.automata.normal import nnf
    assert choice.alternation(nnf(parse_ltlf(text))) == count


def test_deep_until_release_alternation_goes_backward(went_backward, composed):
    """urright06 (five alternating operators, a tie) is progressed; urright08
    (seven) is built backward; with fewer obligations allowed than it has,
    progression again."""
    six = "p1 U (p2 R (p3 U (p4 R (p5 U (p6)))))"
    eight = "p1 U (p2 R (p3 U (p4 R (p5 U (p6 R (p7 U (p8)))))))"
    assert compile_ltlf(six).num_states == 25 and not went_backward
    assert compile_ltlf(eight).num_states == 110 and len(went_backward) == 1
    assert not composed
    check("p1 U (p2 R (p3 U (p4 R (p5 U (p6 R (p7))))))")


def test_past_the_obligations_allowed_it_is_progressed(monkeypatch, went_backward, composed):
    eight = "p1 U (p2 R (p3 U (p4 R (p5 U (p6 R (p7 U (p8)))))))"  # 7 obligations
    progressed = []
    original = compiler.Progression.dfa
    monkeypatch.setattr(compiler.Progression, "dfa", lambda self, *a: progressed.append(1) or original(self, *a))
    monkeypatch.setattr(choice, "AUTO_OBLIGATIONS", 6)
    assert compile_ltlf(eight).num_states == 110
    assert len(went_backward) == 1 and progressed and not composed  # tried, refused before any state
    progressed.clear()
    monkeypatch.setattr(choice, "AUTO_OBLIGATIONS", 7)
    assert compile_ltlf(eight).num_states == 110 and not progressed
