"""Which frequency a label has: the harmonic of its root that holds its content, kept continuous.

A periodic root's frequency is known only modulo Omega, and a root seen from
the other frame moves at several frequencies at once. Each label's
candidates are the frequencies of its content (:func:`label_candidates`);
:func:`continuous_choice` picks one per speed so that the line it draws stays
on one harmonic unless another holds clearly more (see
:mod:`groundres.modes.identify`, step 3).
"""

from __future__ import annotations

import numpy as np

from .participation import ZERO, group_parts

#: A label's frequency moves to another harmonic only where that harmonic
#: holds this many times the content of the one that continues its line.
HARMONIC_RATIO = 2.0
#: The same in rotating axes, where a body direction's content is split between its forward
#: and backward whirl (at ``|omega - Omega|`` and ``omega + Omega``), in a balance that shifts
#: with speed.
ROTATING_RATIO = 10.0


def _merge_equal(freq, energy, scale):
    """Energy of every candidate summed with every other at the same frequency."""
    out = np.zeros_like(energy)
    tol = ZERO * scale[..., None]
    for c in range(freq.shape[-1]):
        same = np.abs(freq - freq[..., c : c + 1]) <= tol
        out[..., c] = (energy * same).sum(-1)
    return out


def continuous_choice(freq, energy, speeds, ratio=HARMONIC_RATIO):
    """Pick one candidate frequency per speed and line, continuously.

    Parameters
    ----------
    freq, energy : ndarray (n_s, n_lines, C)
        Candidate frequencies [rad/s] and the content at each.
    speeds : ndarray (n_s,)
    ratio : float
        A line follows, among the candidates holding at least 1/``ratio`` of
        the largest content, the one nearest its frequency at the
        neighbouring speed; so it leaves a harmonic only where another holds
        ``ratio`` times more.

    Each line starts where its content is most concentrated on one candidate
    (the highest such speed), at the lowest frequency among the candidates
    that hold at least 1/``ratio`` of the largest content, and is continued
    from there both ways.

    Returns
    -------
    pick : int ndarray (n_s, n_lines)
    jump : bool ndarray (n_s, n_lines)
        The pick is not the continuing candidate (the line moved harmonic).
    """
    n_s, n_l, n_c = freq.shape
    raw_total = energy.sum(-1)
    energy = _merge_equal(freq, energy, speeds[:, None])
    top = np.maximum(energy.max(-1), 1e-300)
    # where no candidate holds ratio times the others' content, the lowest
    # frequency among those that share it (e.g. |omega - Omega| for a body
    # direction that whirls as much forward as backward)
    eligible = energy >= top[..., None] / ratio
    pick = np.argmin(np.where(eligible, freq, np.inf), axis=-1)  # (n_s, n_l)
    if n_c == 1 or n_s == 1:
        return pick, np.zeros((n_s, n_l), bool)
    concentration = energy.max(-1) / np.maximum(raw_total, 1e-300)
    most = concentration >= concentration.max(0) - 1e-9
    anchor = n_s - 1 - np.argmax(most[::-1], axis=0)  # (n_l,)
    lines = np.arange(n_l)
    here = np.arange(n_s)[:, None]
    # where only one candidate is eligible it is the pick; elsewhere the line
    # continues from its neighbour towards the anchor, one speed after another
    choice = eligible.sum(-1) > 1
    choice[anchor, lines] = False
    forward = np.flatnonzero((choice & (here > anchor)).any(1))
    backward = np.flatnonzero((choice & (here < anchor)).any(1))[::-1]
    for s, prev in [(s, s - 1) for s in forward] + [(s, s + 1) for s in backward]:
        go = choice[s] & ((s > anchor) if prev < s else (s < anchor))
        gap = np.abs(freq[s] - freq[prev, lines, pick[prev]][:, None])
        cont = np.argmin(np.where(eligible[s], gap, np.inf), axis=-1)
        pick[s] = np.where(go, cont, pick[s])
    # a line moved harmonic where it left a nearer candidate that has content:
    # marked at the later speed of the step, from the neighbour towards the anchor
    prev = np.where(here > anchor, here - 1, here + 1).clip(0, n_s - 1)
    gap = np.abs(freq - np.take_along_axis(freq, pick[..., None], -1)[prev, lines, 0][..., None])
    near = np.argmin(np.where(energy > 1e-6 * top[..., None], gap, np.inf), axis=-1)
    picked = np.take_along_axis(gap, pick[..., None], -1)[..., 0]
    moved = (picked > np.take_along_axis(gap, near[..., None], -1)[..., 0] + 0.25 * speeds[:, None]) & (
        here != anchor
    )
    jump = np.where(here > anchor, moved, np.vstack([np.zeros((1, n_l), bool), moved[:-1]]))
    return pick, jump


def label_candidates(group, position, amp, weight, eigenvalue, orders, speeds):
    """Candidate frequencies of one label along its column, in both frames.

    amp : (n_s, k, M) harmonics of the label's root; weight : (n_s, k);
    eigenvalue : (n_s,). Returns (nr_freq, nr_energy) of shape (n_s, M) and
    (rot_freq, rot_energy) of shape (n_s, P M), P parts per harmonic.
    """
    freq = eigenvalue.imag[:, None] + orders[None, :] * speeds[:, None]  # (n_s, M)
    speed = np.broadcast_to(speeds[:, None], freq.shape)
    parts = group_parts(group, np.moveaxis(amp, 1, -1), weight[:, None, :], freq, speed)
    nr_energy = sum(e[..., position] for e, _ in parts)
    rot_freq = np.concatenate([np.abs(r) for _, r in parts], -1)
    rot_energy = np.concatenate([e[..., position] for e, _ in parts], -1)
    return np.abs(freq), nr_energy, rot_freq, rot_energy
