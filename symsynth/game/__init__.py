"""The manipulation game of docs/game-semantics.md: propositions, moves and
costs in explicit form, and the explicit min-max solver."""
