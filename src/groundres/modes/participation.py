"""What a root contains: its motion, label by label and harmonic by harmonic.

Every root's motion seen from nonrotating axes in multiblade coordinates is
given as harmonics: the amplitude of each coordinate at Im(lambda) + m Omega.
A label is a body direction (or, for an isotropic pair, a forward or
backward whirl), collective, differential, or one half of a cyclic pair: of
the cyclic amplitudes (a, b) at frequency f the forward part (a + i b)/2 is
seen from the rotating blades at f - n Omega and the backward part
(a - i b)/2 at -f - n Omega; the part seen at a negative rotating-frame
frequency is regressive, at a positive one progressive. A body pair (x-y or
pitch-roll) splits likewise into forward and backward whirl by its own
motion, which gives the frequency at which the rotating frame sees it, for
anisotropic bodies too; a body direction without its partner is half
forward, half backward. The content of a label is the kinetic-weighted
(mass-matrix diagonal) squared amplitude of its part.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..model.mbc import Coordinate

_PAIRS = {("x", "y"): "whirl", ("pitch", "roll"): "tilt"}
#: Relative size below which a frequency counts as zero (real roots).
ZERO = 1e-9
#: A cyclic part (or body whirl) seen from the rotating frame at a frequency
#: within this fraction of Omega of zero is only partly regressive or
#: progressive (forward or backward): half each at zero, going over linearly
#: to all one or the other at the band's edges, so that an overdamped cyclic
#: lag mode near Omega is not named by the sign of a vanishing frequency.
STILL_BAND = 0.02


@dataclass(frozen=True)
class Group:
    """Coordinates that make up one or two labels.

    Attributes
    ----------
    labels : tuple of str
    coords : tuple of int
        Indices into the nonrotating coordinates.
    kind : str
        "axial" (collective, differential, body heave or yaw: turned about the
        shaft they look the same, so both frames see them at one frequency),
        "planar" (a body direction without its partner), "pair" (body x-y or
        pitch-roll, anisotropic: one label per direction), "whirl" (an
        isotropic pair: forward and backward whirl), "cyclic" (a cyclic pair
        of order n: regressive and progressive), "inflow" (the inflow states of
        dynamic inflow: the uniform one, or the first-harmonic pair as one label).
    order : int
        n: the rotating frame sees the group's forward part at f - n Omega.
    roots : int
        Roots per label: two (a mode: a conjugate pair, or two real roots), or one (the
        uniform inflow, a first-order state: one real root).
    """

    labels: tuple
    coords: tuple
    kind: str
    order: int
    roots: int = 2


def label_groups(coords: list[Coordinate], isotropic_pairs=()) -> list[Group]:
    """The label groups of a set of nonrotating coordinates, in coordinate order."""
    index = {(c.kind, c.name): i for i, c in enumerate(coords)}
    partner = {}
    for (a, b), word in _PAIRS.items():
        if ("body", a) in index and ("body", b) in index:
            partner[index[("body", a)]] = (index[("body", b)], a, b, word)
    groups, used = [], set()
    for i, c in enumerate(coords):
        if i in used:
            continue
        if i in partner:
            j, a, b, word = partner[i]
            if (a, b) in isotropic_pairs:
                groups.append(Group((f"body forward {word}", f"body backward {word}"), (i, j), "whirl", 1))
            else:
                groups.append(Group((f"body {a}", f"body {b}"), (i, j), "pair", 1))
            used |= {i, j}
        elif c.kind == "inflow" and c.name == "uniform":
            groups.append(Group(("uniform inflow",), (i,), "inflow", 0, roots=1))
        elif c.kind == "inflow":
            pair = tuple(index[("inflow", d)] for d in ("forward", "left"))
            groups.append(Group(("cyclic inflow",), pair, "inflow", 1))
            used |= set(pair)
        elif c.kind == "body" and c.name in ("z", "yaw"):
            groups.append(Group((f"body {c.name}",), (i,), "axial", 0))
        elif c.kind == "body":
            groups.append(Group((f"body {c.name}",), (i,), "planar", 1))
        elif c.name == "0":
            groups.append(Group(("collective lag" if c.kind == "lag" else "coning",), (i,), "axial", 0))
        elif c.name == "d":
            groups.append(Group((f"differential {c.kind}",), (i,), "axial", 0))
        elif c.name.endswith("c"):
            j = index[(c.kind, c.name[:-1] + "s")]
            suffix = "" if c.harmonic == 1 else f" {c.harmonic}"
            groups.append(
                Group(
                    (f"regressive {c.kind}{suffix}", f"progressive {c.kind}{suffix}"),
                    (i, j),
                    "cyclic",
                    c.harmonic,
                )
            )
            used.add(j)
    return groups


def _split(energy, value, scale):
    """Energy to the first label where ``value`` < 0, to the second where > 0 (see STILL_BAND)."""
    band = STILL_BAND * scale
    with np.errstate(invalid="ignore", divide="ignore"):
        g = np.where(
            band > 0,
            np.clip(0.5 - value / np.where(band > 0, 2 * band, 1.0), 0, 1),
            (value < 0) + 0.5 * (value == 0),
        )
    return np.stack([energy * g, energy * (1 - g)], -1)


def group_parts(group: Group, amp, weight, freq, speed):
    """Content of one group at one harmonic.

    Parameters
    ----------
    group : Group
    amp : complex ndarray (..., k)
        Amplitudes of the group's coordinates at signed frequency ``freq``.
    weight : ndarray (..., k)
        Kinetic weights of the coordinates.
    freq, speed : ndarray (...)
        Signed frequency f [rad/s] and rotor speed Omega [rad/s].

    Returns
    -------
    list of (energy, rotating)
        Parts of the motion: ``energy`` (..., n_labels of the group) is the
        weighted squared amplitude per label, ``rotating`` (...) the signed
        frequency at which the rotating frame sees the part.
    """
    sq = weight * np.abs(amp) ** 2
    kind, n = group.kind, group.order
    if kind == "axial" or (kind == "inflow" and n == 0):  # two parts, the second empty
        return [(sq, freq), (0 * sq, freq)]
    if kind == "planar":
        return [(sq / 2, freq - speed), (sq / 2, -freq - speed)]
    a, b = amp[..., 0], amp[..., 1]
    fwd, bwd = np.abs(a + 1j * b) ** 2, np.abs(a - 1j * b) ** 2
    total = fwd + bwd
    share = np.divide(fwd, total, out=np.full_like(total, 0.5), where=total > 0)[..., None]
    rot_f, rot_b = freq - n * speed, -freq - n * speed
    if kind == "pair":
        return [(sq * share, rot_f), (sq * (1 - share), rot_b)]
    if kind == "inflow":  # (the first-harmonic pair: one label, forward and backward parts)
        whole = sq.sum(-1, keepdims=True)
        return [(whole * share, rot_f), (whole * (1 - share), rot_b)]
    energy = sq.sum(-1)
    e_f, e_b = energy * share[..., 0], energy * (1 - share[..., 0])
    if kind == "whirl":  # the forward part at f > 0 whirls forward
        return [(_split(e_f, -freq, speed), rot_f), (_split(e_b, freq, speed), rot_b)]
    return [(_split(e_f, rot_f, speed), rot_f), (_split(e_b, rot_b, speed), rot_b)]


def own_coordinates(group: Group, position: int) -> tuple:
    """Coordinates a label stands for (a direction of an anisotropic pair: its own)."""
    return (group.coords[position],) if group.kind == "pair" else group.coords


def offsets(groups):
    out, k = [], 0
    for g in groups:
        out.append(k)
        k += len(g.labels)
    return out


def label_content(groups, weights, eigenvalue, harmonics, orders, speeds):
    """Energy of every root in every label and at every harmonic.

    Parameters
    ----------
    groups : list of Group
    weights : ndarray (n_s, n)
    eigenvalue : complex ndarray (n_s, n_e)
    harmonics : complex ndarray (n_s, n, M, n_e)
        Amplitude of each coordinate at Im(eigenvalue) + orders[m] Omega.
    orders : int ndarray (M,)
    speeds : ndarray (n_s,)

    Returns
    -------
    energy : ndarray (n_s, n_e, n_labels)
        Summed over harmonics.
    by_order : ndarray (n_s, n_e, M)
        Summed over labels.
    still : ndarray (n_s, n_e, n_groups)
        Share of each group's energy that the rotating frame sees within
        STILL_BAND of zero frequency.
    """
    n_s, _, n_m, n_e = harmonics.shape
    n_labels = sum(len(g.labels) for g in groups)
    energy = np.zeros((n_s, n_e, n_labels))
    by_order = np.zeros((n_s, n_e, n_m))
    still = np.zeros((n_s, n_e, len(groups)))
    speed = np.broadcast_to(speeds[:, None], (n_s, n_e))
    for m, order in enumerate(orders):
        freq = eigenvalue.imag + order * speed
        for k, (g, first) in enumerate(zip(groups, offsets(groups))):
            amp = np.moveaxis(harmonics[:, list(g.coords), m, :], 1, -1)  # (n_s, n_e, k)
            w = weights[:, None, list(g.coords)]
            for e, rot in group_parts(g, amp, w, freq, speed):
                energy[..., first : first + len(g.labels)] += e
                by_order[..., m] += e.sum(-1)
                still[..., k] += e.sum(-1) * (np.abs(rot) <= STILL_BAND * speed)
    group_energy = np.stack(
        [energy[..., f : f + len(g.labels)].sum(-1) for g, f in zip(groups, offsets(groups))], -1
    )
    return energy, by_order, still / np.maximum(group_energy, 1e-300)
