"""LTLf formula families that no one on the project chose (issue 31), for
`bench/ltlf_process.py`: the shapes of the LTLf literature, generated.

Written for symsynth by the LTLf engineer of session 17 (these generators
are ours, not a published benchmark set; each family says where its shape
comes from).  Every family is a list of (name, formula) pairs, smallest
first; plain `X` does not occur (strong next is written `X[!]`, weak `WX`),
so the formulas mean the same under either reading of `X`.

  Rright   p1 R (p2 R (... R pn)): right-nested release chains
  URright  p1 U (p2 R (p3 U ...)): alternating until / release chains
  Uconj    (p1 U q1) & ... & (pn U qn): small conjunctions of untils
  AG       assume-guarantee: (A1 & ... & An) -> (G1 & ... & Gn & mutual exclusion)
           with A_i = G(r_i -> F !r_i) and G_i = G(r_i -> F g_i), pairs of
           processes never granted together (the shape of SYNTCOMP's arbiters)
  Dwyer    the property specification patterns of Dwyer, Avrunin and Corbett
           (ICSE 1999: absence, existence, universality, precedence, response;
           globally, before r, after q, between q and r, after q until r) in the
           finite-trace reading of De Giacomo et al. (AAAI 2014), as
           conjunctions of 1 to 8 instances over fresh atoms
  TV       Tabakov-Vardi style random formulas (the random model of Daniele,
           Giunchiglia and Vardi, CAV 1999, used by Tabakov and Vardi): length L
           over N atoms, binary operators &, U with probability 1/2, unary !, X[!]
           otherwise; N in 2..6, L in 10..40, three seeds each
"""

from __future__ import annotations

import random
import re

Family = list[tuple[str, str]]


def _right_chain(n: int, operator) -> str:
    """p1 OP1 (p2 OP2 (... (pn))), OPi = operator(i)."""
    text = f"p{n}"
    for i in range(n - 1, 0, -1):
        text = f"p{i} {operator(i)} ({text})"
    return text


def rright(sizes=range(2, 17, 2)) -> Family:
    return [(f"rright{n:02d}", _right_chain(n, lambda i: "R")) for n in sizes]


def urright(sizes=range(2, 17, 2)) -> Family:
    return [(f"urright{n:02d}", _right_chain(n, lambda i: "U" if i % 2 else "R")) for n in sizes]


def uconj(sizes=range(1, 9)) -> Family:
    return [(f"uconj{n:02d}", " & ".join(f"(p{i} U q{i})" for i in range(1, n + 1))) for n in sizes]


def assume_guarantee(sizes=range(2, 9)) -> Family:
    out = []
    for n in sizes:
        assume = " & ".join(f"G(r{i} -> F !r{i})" for i in range(1, n + 1))
        respond = [f"G(r{i} -> F g{i})" for i in range(1, n + 1)]
        exclude = [f"G(!(g{i} & g{j}))" for i in range(1, n + 1) for j in range(i + 1, n + 1)]
        out.append((f"ag{n:02d}", f"({assume}) -> ({' & '.join(respond + exclude)})"))
    return out


#: Dwyer et al.'s patterns: (name, template over P, S, T (events) and Q, R (scope bounds)).
DWYER = [
    ("absence-global", "G !P"),
    ("absence-before", "F R -> (!P U R)"),
    ("absence-after", "G(Q -> G !P)"),
    ("absence-between", "G((Q & !R & F R) -> (!P U R))"),
    ("absence-until", "G((Q & !R) -> (!P W R))"),
    ("existence-global", "F P"),
    ("existence-before", "!R W (P & !R)"),
    ("existence-after", "G !Q | F(Q & F P)"),
    ("existence-between", "G((Q & !R) -> (!R W (P & !R)))"),
    ("existence-until", "G((Q & !R) -> (!R U (P & !R)))"),
    ("universality-global", "G P"),
    ("universality-before", "F R -> (P U R)"),
    ("universality-after", "G(Q -> G P)"),
    ("universality-between", "G((Q & !R & F R) -> (P U R))"),
    ("universality-until", "G((Q & !R) -> (P W R))"),
    ("precedence-global", "!P W S"),
    ("precedence-before", "F R -> (!P U (S | R))"),
    ("precedence-after", "G !Q | F(Q & (!P W S))"),
    ("precedence-between", "G((Q & !R & F R) -> (!P U (S | R)))"),
    ("precedence-until", "G((Q & !R) -> (!P W (S | R)))"),
    ("response-global", "G(P -> F S)"),
    ("response-before", "F R -> ((P -> (!R U (S & !R))) U R)"),
    ("response-after", "G(Q -> G(P -> F S))"),
    ("response-between", "G((Q & !R & F R) -> ((P -> (!R U (S & !R))) U R))"),
    ("response-until", "G((Q & !R) -> ((P -> (!R U (S & !R))) W R))"),
    ("chain-response-global", "G(P -> F(S & X[!] F T))"),
    ("bounded-existence-global", "!P W (P W (!P W (P W G !P)))"),
]



def dwyer() -> Family:
    out = [(f"dwyer-{name}", _fill(template, 0)) for name, template in DWYER]
    rng = random.Random(1999)
    for size in (2, 4, 6, 8):
        for seed in range(3):
            picked = [rng.choice(DWYER)[1] for _ in range(size)]  # each over its own atoms
            out.append((f"dwyer-conj{size}-{seed}", " & ".join(f"({_fill(t, k)})" for k, t in enumerate(picked))))
    return out


def _fill(template: str, k: int) -> str:
    """`template` with its pattern letters made atoms p{k}, s{k}, t{k}, q{k}, r{k}
    (the operators U, W, R, G, F, X are not pattern letters: only the single
    letters P, S, T, Q, R as whole words are)."""
    return re.sub(r"\b([PSTQR])\b", lambda m: f"{m[1].lower()}{k}", template)


def tabakov_vardi(atoms=(2, 3, 4, 6), lengths=(10, 20, 30, 40), seeds=3) -> Family:
    out = []
    for n in atoms:
        for length in lengths:
            for seed in range(seeds):
                rng = random.Random(f"tv-{n}-{length}-{seed}")
                out.append((f"tv-n{n}-L{length}-{seed}", _random_formula(rng, n, length)))
    return out


def _random_formula(rng: random.Random, atoms: int, length: int) -> str:
    """A random formula of `length` (atoms and operators counted; the
    recursion is as deep as `length`)."""
    def build(size: int) -> str:
        if size <= 1:
            atom = f"p{rng.randrange(atoms)}"
            return atom if rng.random() < 0.5 else f"!{atom}"
        if size == 2 or rng.random() < 0.5:
            op = rng.choice(["!", "X[!]"])
            return f"{op}({build(size - 1)})"
        left = rng.randrange(1, size - 1)
        op = rng.choice(["&", "U"])
        return f"({build(left)}) {op} ({build(size - 1 - left)})"
    return build(length)


FAMILIES = {
    "Rright": rright,
    "URright": urright,
    "Uconj": uconj,
    "AG": assume_guarantee,
    "Dwyer": dwyer,
    "TV": tabakov_vardi,
}


def generated(names=None) -> dict[str, Family]:
    return {name: make() for name, make in FAMILIES.items() if names is None or name in names}


if __name__ == "__main__":
    for family, items in generated().items():
        for name, text in items[:3]:
            print(family, name, text[:120])
