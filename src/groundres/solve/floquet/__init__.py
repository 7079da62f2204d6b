"""Everything periodic: Floquet exponents from transition matrices integrated on fixed azimuth
grids, the rotor's cyclic symmetry, the lifted eigenproblem, and what a periodic analysis costs."""
