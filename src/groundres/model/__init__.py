"""The case and its equations: reading and checking a case file, the parameters of rotor,
body and dampers, units, and the mass, damping and stiffness matrices with their transforms."""
