"""The symbolic layer: finite-domain variables as bit-vectors, the game's
transition relations with cost bits, and the cost-bounded attractor."""
