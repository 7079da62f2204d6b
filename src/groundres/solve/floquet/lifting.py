"""Multipliers of a periodic matrix product that spans many decades, from its lifted matrix.

At low rotor speeds a well damped mode decays over one period by many
decades, and the eigenvalues of the product of the transition matrices lose
the small multipliers to round-off. Cut into K parts Q_k, the product's
multipliers rho are the K-th powers of the eigenvalues z of the block-cyclic
("lifted") matrix, whose spectrum is well conditioned (the eigenvalue
problem of a periodic matrix product as in Bojanczyk, Golub and Van Dooren
1992, "The periodic Schur decomposition", Proc. SPIE 1770, solved by
reduction to one matrix). Its eigenvectors give the periodic part of each
Floquet solution at every part's start directly (:mod:`groundres.solve.floquet.exponents`).
"""

from __future__ import annotations

import numpy as np


def lifted_eig(parts, g):
    """Multipliers and periodic eigenvectors from transition matrices over K parts.

    Parameters
    ----------
    parts : ndarray (K, m, m)
        Q_k over consecutive equal parts of the reduced period.
    g : ndarray (m, m)
        The symmetry map: R = g' Q_(K-1) ... Q_0.

    Returns
    -------
    z : complex ndarray (m,)
        Eigenvalues of the block-cyclic matrix with arg z in (-pi/K, pi/K]:
        rho = z^K, one z for each rho.
    starts : complex ndarray (K, m, m)
        ``starts[k]`` is Phi(psi_k) v / z^k at the start psi_k of part k: the
        periodic part of the Floquet solution there, for every root (columns).
    """
    k_parts, m, _ = parts.shape
    lifted = np.zeros((k_parts * m, k_parts * m))
    lifted[:m, (k_parts - 1) * m :] = g.T @ parts[-1]
    for k in range(1, k_parts):
        lifted[k * m : (k + 1) * m, (k - 1) * m : k * m] = parts[k - 1]
    values, vectors = np.linalg.eig(lifted)
    # the K roots z of each rho are 2 pi/K apart in angle: exactly one lies in
    # the half-open sector (-pi/K, pi/K] (a negative rho has two on its edges;
    # the sector is turned a little so that round-off cannot take both)
    turn = 1e-7 * np.pi / k_parts
    angle = np.angle(values * np.exp(-1j * turn))
    pick = np.flatnonzero((angle > -np.pi / k_parts) & (angle <= np.pi / k_parts))
    if len(pick) != m:  # round-off at an edge after all: the m nearest the middle
        pick = np.argsort(np.abs(angle), kind="stable")[:m]
    return values[pick], vectors[:, pick].reshape(k_parts, m, m)
