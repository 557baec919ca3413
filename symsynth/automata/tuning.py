"""The sizes that choose between the constructions of an LTLf formula's DFA
(`compose.py`, `products.py`): when a product is made explicitly, from guards
or from moves, when a prefix product applies, when components stay symbolic.
Each was measured on the public LTLf synthesis datasets; the comment says
where.  None changes a result, only its cost.  (`Composer(..., **limits)`
overrides some of them, for tests that force each path.)"""

from __future__ import annotations

from symsynth.automata import moves as moves_

#: Explicit products while both operands have fewer states than this and
#: the product of their state counts is under EXPLICIT_PRODUCT, and while
#: the product has at most EXPLICIT_EDGES edges (an explicit state lists one
#: guard per successor: past that, the attempt is dropped and the operands
#: go symbolic).  Lisa's defaults are 800 and 2,500; ours are larger since an
#: explicit product and its minimization (partition refinement, below) cost
#: little next to a symbolic product's minimization, which works on pairs of
#: states (the counters: 1,025 x 5 states explicit in 0.1 s; symbolic, over
#: a minute).  The edge limit bounds a failed attempt to about a second, and
#: after one, no pair at least as large is tried (see `merge`).  The pairs'
#: bound was 1,000,000 until Nim nim_06_01, whose `G A -> (G B & U)` pairs
#: 730 x 2,909 states, reaches 3,726 of them (818 states minimal) in 12 s
#: explicitly, and did not finish in 280 s as a symbolic product.
EXPLICIT_SINGLE = 100_000
EXPLICIT_PRODUCT = 10_000_000
EXPLICIT_EDGES = 200_000

#: An explicit product made from guards turns to the operands' moves
#: (`_moves_product`) when its states have more than this many successors
#: on average (found early, cheaply): a guard per edge costs what a moves
#: BDD per state does not.  (Before the moves, such a product was dropped
#: for the symbolic product: Nim nim_03_03 then timed out; its 258 x 252
#: states of 256 x 99 successors take 0.64 s on moves.)
EXPLICIT_DEGREE = 100
DENSE_AFTER = 100

#: An explicit product whose operands' successors per state multiply to
#: more than this on average is made from their moves (moves.py: a few BDD
#: operations per product state, where guards cost one per pair of edges).
#: Measured on the products of Nim, Random/Syft and Random/Lydia, both ways
#: (CPU, product and minimization): the moves cost 1.7-13x less from 2,400
#: (Nim nim_03_03's 258 x 252 states of 256 x 99 successors: 0.64 s against
#: 7.5 s), 0.5-1.7x between 90 and 470, and up to 25x more on sparse DFAs
#: (a BDD operation on a state's moves costs 10-100 us in all).
MOVES_PAIRS = 1000
#: ... or when an operand given by its moves only (a dense product's, an
#: invariant's) has more than this many successors per state on average:
#: its edges would have to be split off its moves first, one guard per edge
#: (Nim nim_04_01: 3.0 s that way, 1.2 s on the moves; 16, 32 and 64 gave
#: nim_03_01 0.16, 0.12, 0.12 s and nim_03_02 0.63, 0.69, 0.89 s).
MOVES_DEGREE = moves_.SPARSE_DEGREE

#: An explicit `&` / `|` with an operand of at most this many states that
#: looks a bounded number of letters ahead and a larger one is made by
#: `prefix_product` (cost: one pass over the larger operand's edges).
PREFIX_STATES = 256

#: Two operands over disjoint atoms whose state counts multiply to at most
#: DISJOINT_PAIRS are tried as an explicit product (`Composer._related`),
#: kept when it has no more states than the larger operand: independent
#: parts whose product grows stay apart (GFand's `F q_i`: 2^n states; the
#: invariants `G(a_i -> X b_i)`: 4 x 4 pairs, 6 states, whose many parts a
#: symbolic product in declared order handles best, `symbolic.is_local`).
DISJOINT_PAIRS = 16
#: ... and no more are tried in one `merge` after this many did not shrink.
DISJOINT_TRIES = 4

#: The edge limit of a product grows to this many times the edges of its
#: larger operand (a 16,000-state counter times a 4-state initial condition:
#: 300,000 edges, against a symbolic product of 2^48 codes).
GROWTH = 8

#: ... and to SPARSE_EDGES when the operands' average successors per state
#: multiply to at most SPARSE_DEGREE: a product of sparse DFAs has about as
#: many edges per state as they do, where a symbolic product must find its
#: equivalent pairs by a bisimulation over pairs of states (Double-Counter
#: counters_07: 259 x 259 states of 4 and 5 successors, 65,000 states
#: explicitly; symbolically, over 5 minutes).
SPARSE_DEGREE = 32
SPARSE_EDGES = 2_000_000

#: The components left at the end are multiplied explicitly while the
#: product of their state counts is under this (`Composer.finish`): they
#: read disjoint atoms, and only a product that shrinks when minimized
#: pays (a Syft specification: 536 pairs, 2 states); independent parts
#: whose product does not shrink stay symbolic (GFand: 3 x 2^(n-1) pairs,
#: as many states).
FINAL_PRODUCT = 4096
#: ... and while that times the product of their largest out-degrees (a
#: bound on the explicit product's edges) is under this: independent parts
#: multiply their successors (GFand: 2^n per state).
FINAL_EDGES = 25_000

#: A component of the final symbolic product with at least FACTOR_STATES
#: states and FACTOR_DEGREE successors per state on average is replaced by
#: the operands of its explicit product (`Composer._factored`).
FACTOR_STATES = 64
FACTOR_DEGREE = 16

#: A conjunction of bounded-lookahead invariants is one leaf while its DFA
#: has at most MERGED_EDGES edges (built by progression) or, when it looks
#: one step ahead (invariant.py, which costs per state), at most
#: MERGED_INVARIANT_EDGES edges; past that, part by part.  (Nim nim_06_01's
#: system invariant: 1,460 states and 568,683 edges in 1.5 s as one leaf;
#: part by part, products past the edge limits and a symbolic product that
#: did not finish in 280 s.)  A dense merged leaf that ends in the final
#: symbolic product is replaced there by its parts, composed as they would
#: have been (`Composer._factored`): the random Syft guarantees (`G(!X p |
#: q)` and mutual exclusions, a state remembering the last letter and
#: reaching most others, 256 successors per state) cost less that way.
#: (Until session 19 a bound of 64 successors per state on average kept
#: such leaves apart from the start, and Nim's with them: 136 per state at
#: five heaps, 389 at six.)
MERGED_EDGES = 2000
MERGED_INVARIANT_EDGES = 2_000_000
