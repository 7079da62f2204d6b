"""What each root is: its label, its frequency in both frames, its harmonics.

Shared by every method (multiblade eigen-analysis, rotating-axes
eigen-analysis, Floquet analysis), so that the same root gets the same name
and the same frequencies whichever method found it.

The input is every root's motion seen from nonrotating axes in multiblade
coordinates, as harmonics: the amplitude of each coordinate at the
frequencies Im(lambda) + m Omega. A time-invariant multiblade analysis has
the single harmonic m = 0; rotating-axes and Floquet analyses have several,
because the motion of a periodic system (or of a body turning with the rotor)
is periodic times exp(lambda t) (Peters, Lieb and Ahaus 2011, "Interpretation
of Floquet eigenvalues and eigenvectors for periodic systems", JAHS 56,
032001). From it:

1. **Content.** The kinetic-weighted squared amplitude of each label at each
   harmonic. A label is a body direction (or, for an isotropic pair, a
   forward or backward whirl), collective, differential, or one half of a
   cyclic pair: of the cyclic amplitudes (a, b) at frequency f the forward
   part (a + i b)/2 is seen from the rotating blades at f - n Omega and the
   backward part (a - i b)/2 at -f - n Omega; the part seen at a negative
   rotating-frame frequency is regressive, at a positive one progressive.
2. **Labels.** At every speed each mode (a conjugate pair of roots) takes the
   label its content ranks first, by optimal assignment so that every label
   is used once. Where two labels are within :data:`LABEL_MARGIN` of each
   other a mode keeps the label it had at the previous speed (no flicker);
   exact ties go by a fixed rule; a growing mode always takes the label it
   ranks first.
3. **Frequencies.** A periodic root's frequency is known only modulo Omega.
   The frequency given for a mode is the one at which its labelled content
   moves: the harmonic that holds the largest share of that label's content,
   kept continuous along the label's line (it moves to another harmonic only
   where that one holds :data:`HARMONIC_RATIO` times more, and such a speed
   is flagged). As the dissimilarity of a periodic system vanishes its
   content goes to a single harmonic per root, so the diagram goes to the
   time-invariant one mode by mode. In rotating axes the same, from the
   rotating-frame frequencies of the label's content; a body mode's split into
   forward and backward whirl follows from its own x-y (pitch-roll) motion,
   for anisotropic bodies too (a body direction without its partner is half
   forward, half backward).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import linear_sum_assignment

from .mbc import Coordinate

_PAIRS = {("x", "y"): "whirl", ("pitch", "roll"): "tilt"}
#: Content fraction within which a label stays with the mode that had it.
LABEL_MARGIN = 0.05
#: A label's frequency moves to another harmonic only where that harmonic
#: holds this many times the content of the one that continues its line.
HARMONIC_RATIO = 2.0
#: Harmonics kept each side of the identified one (``Modes.harmonics``).
WINDOW = 8
#: Relative size below which a frequency counts as zero (real roots).
_ZERO = 1e-9
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
        "blade" (collective or differential: the same in both frames),
        "planar" (a body direction without its partner), "pair" (body x-y or
        pitch-roll, anisotropic: one label per direction), "whirl" (an
        isotropic pair: forward and backward whirl), "cyclic" (a cyclic pair
        of order n: regressive and progressive).
    order : int
        n: the rotating frame sees the group's forward part at f - n Omega.
    """

    labels: tuple
    coords: tuple
    kind: str
    order: int


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
        elif c.kind == "body":
            groups.append(Group((f"body {c.name}",), (i,), "planar", 1))
        elif c.name == "0":
            groups.append(Group(("collective lag" if c.kind == "lag" else "coning",), (i,), "blade", 0))
        elif c.name == "d":
            groups.append(Group((f"differential {c.kind}",), (i,), "blade", 0))
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
    if kind == "blade":  # two parts like every other kind, the second empty
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
    energy = sq.sum(-1)
    e_f, e_b = energy * share[..., 0], energy * (1 - share[..., 0])
    if kind == "whirl":  # the forward part at f > 0 whirls forward
        return [(_split(e_f, -freq, speed), rot_f), (_split(e_b, freq, speed), rot_b)]
    return [(_split(e_f, rot_f, speed), rot_f), (_split(e_b, rot_b, speed), rot_b)]


def _own(group: Group, position: int) -> tuple:
    """Coordinates a label stands for (a direction of an anisotropic pair: its own)."""
    return (group.coords[position],) if group.kind == "pair" else group.coords


def _offsets(groups):
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
        for k, (g, first) in enumerate(zip(groups, _offsets(groups))):
            amp = np.moveaxis(harmonics[:, list(g.coords), m, :], 1, -1)  # (n_s, n_e, k)
            w = weights[:, None, list(g.coords)]
            for e, rot in group_parts(g, amp, w, freq, speed):
                energy[..., first : first + len(g.labels)] += e
                by_order[..., m] += e.sum(-1)
                still[..., k] += e.sum(-1) * (np.abs(rot) <= STILL_BAND * speed)
    group_energy = np.stack(
        [energy[..., f : f + len(g.labels)].sum(-1) for g, f in zip(groups, _offsets(groups))], -1
    )
    return energy, by_order, still / np.maximum(group_energy, 1e-300)


@dataclass
class Modes:
    """Labelled modes over a sweep: one column per label.

    A mode is a conjugate pair of roots (or two real roots where it is
    overdamped). At each speed every label is carried by the mode whose
    content it ranks first (see the module docstring), so labels follow the
    physics through crossings and veerings.

    Attributes
    ----------
    labels : list of str
    eigenvalue : complex ndarray (n_s, n_m)
        Representative root with its frequency seen from nonrotating axes,
        Im >= 0 [1/s].
    real_part : ndarray (n_s, n_m)
        Largest real part of the mode's two roots [1/s].
    frequency_nonrotating, frequency_rotating : ndarray (n_s, n_m)
        Frequency [rad/s] seen from nonrotating and from rotating axes.
    shape : complex ndarray (n_s, n, n_m)
        Mode shape seen from nonrotating axes: amplitude of each nonrotating
        (body, multiblade) coordinate at the mode's frequency.
    energy : ndarray (n_s, n_m, n_m)
        Fraction of the mode's weighted squared amplitude in each label.
    branch, partner : int ndarray (n_s, n_m)
        The two tracked roots (columns of the solver's solution) of the mode
        that carries the label, the representative first: where they change
        the label moved to another branch.
    exchange : bool ndarray (n_s, n_m)
        The label moved to another branch between the previous speed and this
        one (a veering, where two branches exchange their character).
    root_label : int ndarray (n_s, n_e)
        Label (index into ``labels``) of the mode each tracked root belongs to.
    root_real_part : ndarray (n_s, n_e)
        Real part of each tracked root [1/s]; the two roots of an overdamped
        mode differ, those of a conjugate pair agree.
    harmonic_change, harmonic_change_rotating : bool ndarray (n_s, n_m)
        The label's frequency moved to another harmonic of its root at this
        speed (periodic systems only): its content there is clearly larger.
    participation : ndarray (n_s, n_m, 2 h + 1)
        Share of the mode's motion seen from nonrotating axes at the
        frequency offsets ``harmonic_orders`` * Omega from the identified one.
    harmonics : complex ndarray (n_s, n, 2 h + 1, n_m)
        The whole periodic shape: amplitude of each nonrotating coordinate at
        frequency Im(eigenvalue) + harmonic_orders * Omega.
    harmonic_orders : int ndarray (2 h + 1,)
        -h..h (h = 0 for a time-invariant multiblade analysis).
    """

    labels: list
    eigenvalue: np.ndarray
    real_part: np.ndarray
    frequency_nonrotating: np.ndarray
    frequency_rotating: np.ndarray
    shape: np.ndarray
    energy: np.ndarray
    branch: np.ndarray
    partner: np.ndarray
    exchange: np.ndarray
    root_label: np.ndarray
    root_real_part: np.ndarray
    harmonic_change: np.ndarray
    harmonic_change_rotating: np.ndarray
    participation: np.ndarray
    harmonics: np.ndarray
    harmonic_orders: np.ndarray

    @property
    def damping_ratio(self) -> np.ndarray:
        """-Re(lambda)/|lambda| of the least damped root of each mode [-]."""
        lam = self.eigenvalue
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.where(np.abs(lam) > 0, -lam.real / np.abs(lam), np.nan)

    @property
    def orders(self) -> np.ndarray:
        """Alias of ``harmonic_orders`` (the ``harmonic`` coordinate of modes.nc)."""
        return self.harmonic_orders

    def successor(self) -> np.ndarray:
        """Label index, at the next speed, of the branch that carries each label: (n_s - 1, n_m).

        Equal to the label itself except where labels exchange branches.
        """
        n_s, n_m = self.branch.shape
        nxt = np.full((n_s - 1, max(self.branch.max(initial=0), self.partner.max(initial=0)) + 1), -1)
        rows = np.arange(n_s - 1)[:, None]
        nxt[rows, self.partner[1:]] = np.arange(n_m)
        nxt[rows, self.branch[1:]] = np.arange(n_m)
        out = nxt[rows, self.branch[:-1]]
        return np.where(out >= 0, out, nxt[rows, self.partner[:-1]])


# -- pairing roots into modes and labelling them ----------------------------------


def _best_matching(items, cost):
    """Pairs of ``items`` of least total ``cost[a, b]`` (all pairings up to 10 items, else greedy)."""
    items = list(items)
    if len(items) > 10:
        out, left = [], items
        while len(left) > 1:
            a, b = min(((a, b) for a in left for b in left if a < b), key=lambda p: cost[p])
            out.append((a, b))
            left = [i for i in left if i not in (a, b)]
        return out

    def best(left):
        if len(left) < 2:
            return 0.0, []
        first, rest = left[0], left[1:]
        options = []
        for i, b in enumerate(rest):
            total, pairs = best(rest[:i] + rest[i + 1 :])
            options.append((total + cost[first, b], [(first, b)] + pairs))
        return min(options, key=lambda o: o[0])

    return best(items)[1]


def _pair_roots(z, frac, sigma, still, shapes, previous=None):
    """Group the roots of one block at one speed into modes.

    ``z`` is each root's pairing key (the eigenvalue, or the Floquet
    multiplier): keys above the real axis pair with the nearest conjugate
    below it. Real keys pair by least total cost over all pairings. Two roots
    whose motion is at zero frequency (``still`` near 1: an overdamped
    oscillator) cost 1 - MAC of their shapes (``shapes``, weighted harmonics,
    one row per root), plus one if both lie on the same side of the median of
    the still roots: the two roots of one overdamped oscillator move alike,
    one slow and one fast; two roots of one degenerate cluster do neither
    (their shapes are any basis of the cluster). Two real keys whose motion is at a nonzero frequency (an
    overdamped cyclic lag seen at Omega from nonrotating axes, a parametric
    root at Omega/2) are the halves of a conjugate pair of that frequency that
    the periodic analysis cannot tell apart: they also cost the relative
    difference of their real parts ``sigma``, as the time-invariant analysis
    of the same system would pair them. A zero-frequency root with a moving
    one costs one more. Real roots that were paired at the previous speed
    (``previous``: each column's partner there, or None) stay paired while
    both are real, so that a mode's roots do not change partners (and its
    real part jump) from one speed to the next. Returns a list of
    (representative, other): the representative has Im z >= 0, or the larger
    modulus of two real keys.
    """
    small = _ZERO * np.maximum(np.abs(z), 1e-300)
    upper = np.flatnonzero(z.imag > small)
    lower = np.flatnonzero(z.imag < -small)
    rest = list(np.flatnonzero(np.abs(z.imag) <= small))
    pairs = []
    if len(upper) and len(lower):
        r, c = linear_sum_assignment(np.abs(z[upper][:, None] - z[lower][None, :].conj()))
        pairs += [(upper[i], lower[j]) for i, j in zip(r, c)]
        rest += [upper[i] for i in set(range(len(upper))) - set(r)]
        rest += [lower[j] for j in set(range(len(lower))) - set(c)]
    else:
        rest += list(upper) + list(lower)
    if previous is not None:
        kept = [(a, int(previous[a])) for a in rest if int(previous[a]) in rest and a < previous[a]]
        pairs += kept
        done = {i for p in kept for i in p}
        rest = [a for a in rest if a not in done]
    if rest:
        idx = np.array(rest)
        content = np.abs(frac[idx][:, None] - frac[idx][None, :]).sum(-1)
        sg = sigma[idx]
        apart = np.abs(sg[:, None] - sg[None, :]) / (np.abs(sg[:, None]) + np.abs(sg[None, :]) + 1e-300)
        st = still[idx]
        both_still = st[:, None] * st[None, :]
        both_moving = (1 - st[:, None]) * (1 - st[None, :])
        v = shapes[idx]
        gram = np.abs(v.conj() @ v.T) ** 2
        norm = np.real(np.einsum("ij,ij->i", v.conj(), v))
        mac = gram / np.maximum(np.outer(norm, norm), 1e-300)
        # two still roots on the same side of the still roots' median value
        # (or of equal value) belong to two oscillators, not one
        still_sg = sg[st > 0.5]
        mid = np.median(still_sg) if len(still_sg) else 0.0
        same_side = ((sg[:, None] - mid) * (sg[None, :] - mid) >= 0) | (apart < 1e-3)
        cost = (
            both_still * (1 - mac + same_side)
            + both_moving * (content + apart)
            + (1 - both_still - both_moving)
        )
        local = _best_matching(range(len(idx)), cost)
        pairs += [(idx[a], idx[b]) for a, b in local]
    key = lambda j: (z[j].imag >= 0, abs(z[j]))  # noqa: E731
    return [(a, b) if key(a) >= key(b) else (b, a) for a, b in pairs]


def _pairs(z, frac, sigma, still, shapes):
    """Representative and other root of every mode at every speed: (n_s, n_e/2) each."""
    n_s, n_e = z.shape
    half = n_e // 2
    small = _ZERO * np.maximum(np.abs(z), 1e-300)
    upper = z.imag > small
    plain = upper.sum(-1) == half
    reps = np.argsort(~upper, axis=-1, kind="stable")[:, :half]
    partner = np.argmin(np.abs(z[:, :, None] - z[:, None, :].conj()), axis=-1)
    others = np.take_along_axis(partner, reps, -1)
    for k in np.flatnonzero(~plain):  # in speed order: real roots keep their partners
        previous = None
        if k > 0:
            previous = np.empty(n_e, int)
            previous[reps[k - 1]] = others[k - 1]
            previous[others[k - 1]] = reps[k - 1]
        reps[k], others[k] = zip(*_pair_roots(z[k], frac[k], sigma[k], still[k], shapes[k], previous))
    return reps, others


def _assign(score, real_part, threshold):
    """Label of every mode at every speed, by content (see the module docstring).

    score : (n_s, n_m, n_l) content fraction of each mode in each label;
    real_part : (n_s, n_m); threshold : (n_s,) growth threshold.
    Returns choice (n_s, n_m): label index of each mode.

    A mode keeps its previous label (within the margin) when one mode of the
    previous speed is clearly the nearest to it in real part and content:
    physical quantities only, so that every method continues the same way;
    where two roots have just met and parted (an exceptional point) neither
    continues the other, and the content alone decides.
    """
    n_s, n_m, n_l = score.shape
    choice = np.argmax(score, axis=-1)
    if n_l == 1:
        return choice
    top2 = np.sort(score, axis=-1)[..., -2:]
    clear = (np.sort(choice, -1) == np.arange(n_l)).all(-1) & (
        (top2[..., -1] - top2[..., 0]).min(-1) > LABEL_MARGIN
    )
    # exact ties: the mode with the larger real part takes the label listed first
    rank = np.argsort(np.argsort(-real_part, axis=-1, kind="stable"), axis=-1)
    tie = 1e-6 * (1 - rank[..., :, None] / n_m) * (1 - np.arange(n_l) / n_l)
    for k in np.flatnonzero(~clear):  # in speed order: each needs the previous speed's labels
        sc = score[k] + tie[k]
        if k > 0:
            scale = np.abs(real_part[k]).max() + 1e-300
            d = np.abs(real_part[k][:, None] - real_part[k - 1][None, :]) / scale
            d = d + np.abs(score[k][:, None] - score[k - 1][None, :]).sum(-1)  # (now, before)
            order = np.sort(d, axis=-1)
            nearest = np.argmin(d, axis=-1)
            sure = order[:, 0] <= 0.5 * order[:, 1]
            sc[np.flatnonzero(sure), choice[k - 1, nearest[sure]]] += LABEL_MARGIN
        grows = real_part[k] > threshold[k]
        sc[grows, choice[k, grows]] += 10.0  # a growing mode takes its top label
        choice[k] = linear_sum_assignment(-sc)[1]
    return choice


def _order_still(choice, real, share, first, second):
    """Where the two modes carrying a cyclic pair's labels (or an isotropic
    body's whirls) are both seen at about zero frequency from the rotating
    frame (an overdamped cyclic lag near Omega, a body whirl near zero), the
    sign of that frequency names nothing: the less damped takes the first
    label (regressive; forward). Modifies ``choice`` (n_s, n_m) in place."""
    for s in range(choice.shape[0]):
        a = np.flatnonzero(choice[s] == first)
        b = np.flatnonzero(choice[s] == second)
        if (
            len(a)
            and len(b)
            and share[s, a[0]] > 0.5
            and share[s, b[0]] > 0.5
            and real[s, b[0]] > real[s, a[0]]
        ):
            choice[s, a[0]], choice[s, b[0]] = second, first


def _merge_equal(freq, energy, scale):
    """Energy of every candidate summed with every other at the same frequency."""
    out = np.zeros_like(energy)
    tol = _ZERO * scale[..., None]
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
    (the highest such speed) and is continued from there both ways; ties go
    to the lower frequency.

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
    near = energy >= top[..., None] * (1 - 1e-9)
    best = np.argmin(np.where(near, freq, np.inf), axis=-1)  # (n_s, n_l)
    pick = best.copy()
    jump = np.zeros((n_s, n_l), bool)
    if n_c == 1 or n_s == 1:
        return pick, jump
    concentration = energy.max(-1) / np.maximum(raw_total, 1e-300)
    most = concentration >= concentration.max(0) - 1e-9
    anchor = n_s - 1 - np.argmax(most[::-1], axis=0)  # (n_l,)
    lines = np.arange(n_l)

    def step(s, prev):
        go = (s > anchor) if prev < s else (s < anchor)
        if not go.any():
            return
        gap = np.abs(freq[s] - freq[prev, lines, pick[prev]][:, None])
        e_best = energy[s, lines, best[s]][:, None]
        # the line follows the nearest candidate holding at least 1/ratio of the
        # largest content; it changed harmonic if it left a nearer one with content
        cont = np.argmin(np.where(energy[s] >= e_best / ratio, gap, np.inf), axis=-1)
        near = np.argmin(np.where(energy[s] > 1e-6 * e_best, gap, np.inf), axis=-1)
        moved = gap[lines, cont] > gap[lines, near] + 0.25 * speeds[s]
        pick[s] = np.where(go, cont, pick[s])
        jump[s] = np.where(go, moved, jump[s])

    for s in range(1, n_s):
        step(s, s - 1)
    for s in range(n_s - 2, -1, -1):
        step(s, s + 1)
    # a backward step from s + 1 to s is marked at s + 1, the later speed
    back = np.zeros_like(jump)
    back[1:] = jump[:-1]
    jump = np.where(np.arange(n_s)[:, None] > anchor, jump, back)
    return pick, jump


def _label_candidates(group, position, amp, weight, eigenvalue, orders, speeds):
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


def _window(array, centre, h, axis_len):
    """array[..., centre + k] for k = -h..h along the last axis (zero outside)."""
    k = centre[..., None] + np.arange(-h, h + 1)
    inside = (k >= 0) & (k < axis_len)
    out = np.take_along_axis(array, np.clip(k, 0, axis_len - 1), axis=-1)
    return np.where(inside, out, 0)


def identify(
    eigenvalue,
    harmonics,
    orders,
    coords,
    weights,
    speeds,
    *,
    block=None,
    blocks=None,
    key=None,
    isotropic_pairs=(),
    threshold=None,
) -> Modes:
    """Label the roots of a sweep and give their frequencies in both frames.

    Parameters
    ----------
    eigenvalue : complex ndarray (n_s, n_e)
        Roots, one column per tracked branch (for a periodic system any
        representative modulo Omega).
    harmonics : complex ndarray (n_s, n, M, n_e)
        Amplitude of each nonrotating coordinate at Im(eigenvalue) + orders * Omega.
    orders : int ndarray (M,)
    coords : list of Coordinate
        Nonrotating coordinates (body, multiblade).
    weights : ndarray (n_s, n)
        Kinetic weight (mass-matrix diagonal) of each coordinate.
    speeds : ndarray (n_s,)
    block, blocks : optional
        Coupling block of each column and the coordinates of each block (roots
        of a block carry only that block's labels); one block by default.
    key : complex ndarray (n_s, n_e), optional
        What pairs conjugate roots: the eigenvalue by default; the Floquet
        multiplier for a periodic system (exponents are conjugate modulo Omega).
    isotropic_pairs : iterable of (str, str)
        Body pairs that are isotropic, so move in whirls.
    threshold : ndarray (n_s,), optional
        Real part [1/s] above which a root grows; a growing mode takes the label
        its content ranks first.
    """
    n_s, n, n_m_h, n_e = harmonics.shape
    groups = label_groups(coords, isotropic_pairs)
    labels = [name for g in groups for name in g.labels]
    owner = [(g, i) for g in groups for i in range(len(g.labels))]
    key = eigenvalue if key is None else key
    threshold = np.zeros(n_s) if threshold is None else np.asarray(threshold, float)
    if blocks is None:
        blocks, block = [np.arange(n)], np.zeros(n_e, int)
    energy, by_order, still_group = label_content(groups, weights, eigenvalue, harmonics, orders, speeds)
    total = energy.sum(-1, keepdims=True)
    frac = energy / np.where(total > 0, total, 1.0)
    # share of each root's motion at (nearly) zero frequency
    near = np.maximum(0.25 * speeds, _ZERO * np.abs(eigenvalue).max(-1))[:, None, None]  # (at rest: zero)
    at_zero = np.abs(eigenvalue.imag[..., None] + orders * speeds[:, None, None]) <= near
    still = (by_order * at_zero).sum(-1) / np.maximum(by_order.sum(-1), 1e-300)
    n_l = len(labels)
    rep = np.zeros((n_s, n_l), int)
    other = np.zeros((n_s, n_l), int)
    for blk, members in enumerate(blocks):
        cols = np.flatnonzero(block == blk)
        mine = np.array([i for i, (g, pos) in enumerate(owner) if set(_own(g, pos)) <= set(members.tolist())])
        if 2 * len(mine) != len(cols):
            raise RuntimeError(f"block of {len(members)} coordinates has labels {[labels[i] for i in mine]}")
        frac_b = frac[:, cols][:, :, mine]
        shapes = np.moveaxis(harmonics[:, :, :, cols] * np.sqrt(weights)[:, :, None, None], -1, 1)
        shapes = shapes.reshape(n_s, len(cols), -1)  # weighted harmonics of each root
        reps, others = _pairs(key[:, cols], frac_b, eigenvalue[:, cols].real, still[:, cols], shapes)
        rows = np.arange(n_s)[:, None]
        score = (frac_b[rows, reps] + frac_b[rows, others]) / 2
        real = np.maximum(eigenvalue[:, cols][rows, reps].real, eigenvalue[:, cols][rows, others].real)
        choice = _assign(score, real, threshold)
        for k, g in enumerate(groups):
            if g.kind in ("cyclic", "whirl") and g.coords[0] in members:
                first = mine.tolist().index(_offsets(groups)[k])
                share = (still_group[:, cols, k][rows, reps] + still_group[:, cols, k][rows, others]) / 2
                _order_still(choice, real, share, first, first + 1)
        inverse = np.argsort(choice, axis=-1)  # mode holding each label
        rep[:, mine] = cols[np.take_along_axis(reps, inverse, -1)]
        other[:, mine] = cols[np.take_along_axis(others, inverse, -1)]
    rows = np.arange(n_s)[:, None]
    lam, lam_other = eigenvalue[rows, rep], eigenvalue[rows, other]

    # frequencies: candidates of each label on its own root
    nr_f, nr_e, rot_f, rot_e = [], [], [], []
    for j, (g, position) in enumerate(owner):
        amp = harmonics[np.arange(n_s)[:, None], list(g.coords), :, rep[:, j : j + 1]]  # (n_s, k, M)
        cand = _label_candidates(g, position, amp, weights[:, list(g.coords)], lam[:, j], orders, speeds)
        for store, value in zip((nr_f, nr_e, rot_f, rot_e), cand):
            store.append(value)
    nr_f, nr_e, rot_f, rot_e = (np.stack(x, 1) for x in (nr_f, nr_e, rot_f, rot_e))
    pick, jump = continuous_choice(nr_f, nr_e, speeds)
    pick_r, jump_r = continuous_choice(rot_f, rot_e, speeds)
    f_nr = np.take_along_axis(nr_f, pick[..., None], -1)[..., 0]
    f_rot = np.take_along_axis(rot_f, pick_r[..., None], -1)[..., 0]

    # the identified harmonic as the mode's own: positive frequency, window around it
    signed = lam.imag + orders[pick] * speeds[:, None]
    flip = signed < 0
    h = min(WINDOW, (len(orders) - 1) // 2)
    harm = np.take_along_axis(harmonics, rep[:, None, None, :], axis=3)  # (n_s, n, M, n_l)
    harm = np.moveaxis(harm, 2, -1)  # (n_s, n, n_l, M)
    centre = np.broadcast_to(pick[:, None, :], harm.shape[:-1])
    window = _window(harm, centre, h, len(orders))
    window = np.where(flip[:, None, :, None], window[..., ::-1].conj(), window)
    share = by_order[rows, rep]  # (n_s, n_l, M)
    share = share / np.maximum(share.sum(-1, keepdims=True), 1e-300)
    part = _window(share, pick, h, len(orders))
    part = np.where(flip[..., None], part[..., ::-1], part)
    eig = lam.real + 1j * f_nr
    moved = np.zeros((n_s, n_l), bool)
    moved[1:] = (rep[1:] != rep[:-1]) & (rep[1:] != other[:-1])
    root_label = np.zeros((n_s, n_e), int)
    root_label[rows, other] = np.arange(n_l)
    root_label[rows, rep] = np.arange(n_l)
    return Modes(
        labels=labels,
        eigenvalue=eig,
        real_part=np.maximum(lam.real, lam_other.real),
        frequency_nonrotating=f_nr,
        frequency_rotating=f_rot,
        shape=window[..., h],
        energy=(frac[rows, rep] + frac[rows, other]) / 2,
        branch=rep,
        partner=other,
        exchange=moved,
        root_label=root_label,
        root_real_part=eigenvalue.real.copy(),
        harmonic_change=jump,
        harmonic_change_rotating=jump_r,
        participation=part,
        harmonics=np.moveaxis(window, -1, 2),
        harmonic_orders=np.arange(-h, h + 1),
    )
