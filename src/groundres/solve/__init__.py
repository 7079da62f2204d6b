"""Roots of the equations at any rotor speed: eigen-analysis of the time-invariant forms,
Floquet analysis of the periodic ones (:mod:`groundres.solve.floquet`), time simulation."""
