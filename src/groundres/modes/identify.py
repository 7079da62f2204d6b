"""What each root is: its label, its frequency in both frames, its harmonics.

Shared by every method (multiblade eigen-analysis, rotating-axes
eigen-analysis, Floquet analysis), so that the same root gets the same name
and the same frequencies whichever method found it. The input is every
root's motion seen from nonrotating axes in multiblade coordinates, as
harmonics (Peters, Lieb and Ahaus 2011, "Interpretation of Floquet
eigenvalues and eigenvectors for periodic systems", JAHS 56, 032001): a
time-invariant multiblade analysis has the single harmonic m = 0, a
rotating-axes or Floquet analysis several. From it:

1. **Content** of each root per label and harmonic (:mod:`groundres.modes.participation`)
   and the **modes**, pairs of roots (:mod:`groundres.modes.pairing`).
2. **Labels.** At every speed each mode takes the label its content ranks
   first, by optimal assignment so that every label is used once. Where two
   labels are within :data:`LABEL_MARGIN` of each other a mode keeps the
   label of the mode of the previous speed that is clearly nearest to it in
   real part and content (physical quantities only, so every method
   continues the same way); exact ties go to the less damped mode in label
   order; a growing mode always takes the label it ranks first. Two modes
   that carry a cyclic pair's labels (or an isotropic body's whirls) while
   both are seen at about zero frequency from the rotating frame (an
   overdamped cyclic lag near Omega) are named by damping: the less damped is
   regressive (forward).
3. **Frequencies.** A periodic root's frequency is known only modulo Omega.
   The frequency given for a mode is the one at which its labelled content
   moves: the harmonic that holds the largest share of that label's content,
   kept continuous along the label's line (it moves to another harmonic only
   where that one holds :data:`groundres.modes.frequencies.HARMONIC_RATIO` times more, and such a speed
   is flagged). As the dissimilarity of a periodic system vanishes its
   content goes to a single harmonic per root, so the diagram goes to the
   time-invariant one mode by mode. In rotating axes the same, from the
   rotating-frame frequencies of the label's content (:data:`groundres.modes.frequencies.ROTATING_RATIO`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import linear_sum_assignment

from .frequencies import ROTATING_RATIO, continuous_choice, label_candidates
from .pairing import pair_roots
from .participation import ZERO, label_content, label_groups, offsets, own_coordinates

#: Content fraction within which a label stays with the mode that had it.
LABEL_MARGIN = 0.05
#: Harmonics kept each side of the identified one (``Modes.harmonics``).
WINDOW = 8


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
        Im >= 0 [1/s]: of two real roots, the less damped.
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
    root_eigenvalue : complex ndarray (n_s, n_e)
        Each tracked root as the solver found it [1/s] (a Floquet exponent's
        frequency known modulo the rotor speed); ``root_real_part`` its real
        part: the two roots of an overdamped mode differ, those of a conjugate
        pair agree.
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
    root_eigenvalue: np.ndarray
    harmonic_change: np.ndarray
    harmonic_change_rotating: np.ndarray
    participation: np.ndarray
    harmonics: np.ndarray
    harmonic_orders: np.ndarray

    @property
    def root_real_part(self) -> np.ndarray:
        return self.root_eigenvalue.real

    @property
    def damping_ratio(self) -> np.ndarray:
        """Damping ratio of each mode's representative root (:func:`damping_ratio`) [-]."""
        return damping_ratio(self.eigenvalue)

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


def damping_ratio(roots, scale=None) -> np.ndarray:
    """``-Re(lambda)/|lambda|`` [-]; 0 for a root at the origin.

    A root at the origin (``|lambda|`` below 1e-12 of ``scale``, by default the
    largest root along the last axis) is a neutral mode with no restoring
    force, such as a free hinge at rest: it neither grows nor decays, so its
    damping ratio is 0, between the decaying (+1) and the growing (-1) real
    roots on either side of it (``docs/conventions.md``).
    """
    roots = np.asarray(roots)
    size = np.abs(roots)
    scale = size.max(-1, keepdims=True) if scale is None else scale
    zero = size <= 1e-12 * np.maximum(scale, 1e-300)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(zero, 0.0, -roots.real / np.where(zero, 1.0, size))


# -- labelling modes ----------------------------------------------------------


def _assign(score, real_part, threshold, size):
    """Label of every mode at every speed, by content (see the module docstring).

    score : (n_s, n_m, n_l) content fraction of each mode in each label;
    real_part : (n_s, n_m); threshold : (n_s,) growth threshold; size : (n_s,)
    the scale real parts are compared on (the same for every method).
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
            d = np.abs(real_part[k][:, None] - real_part[k - 1][None, :]) / size[k]
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
    rows = np.arange(choice.shape[0])
    a = np.argmax(choice == first, axis=-1)  # mode holding each label (every label is held)
    b = np.argmax(choice == second, axis=-1)
    swap = (share[rows, a] > 0.5) & (share[rows, b] > 0.5) & (real[rows, b] > real[rows, a])
    choice[rows[swap], a[swap]] = second
    choice[rows[swap], b[swap]] = first


def _merge_blocks(blocks, block, owned):
    """Coupling blocks joined where one label stands for coordinates of several
    (at rest the cyclic lag pair can split between the hub directions)."""
    where = {int(c): b for b, members in enumerate(blocks) for c in members}
    parent = list(range(len(blocks)))

    def root(b):
        while parent[b] != b:
            b = parent[b]
        return b

    for coords in owned:
        first = root(where[coords[0]])
        for c in coords[1:]:
            parent[root(where[c])] = first
    roots = sorted({root(b) for b in range(len(blocks))})
    if len(roots) == len(blocks):
        return blocks, block
    merged = [np.sort(np.concatenate([blocks[b] for b in range(len(blocks)) if root(b) == r])) for r in roots]
    new_index = np.array([roots.index(root(b)) for b in range(len(blocks))])
    return merged, new_index[block]


def _at(x, cols, axis=1):
    """x's entries (n_s, ...) of a block's roots ``cols`` (n_s, m) along ``axis``, speed by speed."""
    shape = [1] * x.ndim
    shape[0], shape[axis] = len(cols), cols.shape[1]
    return np.take_along_axis(x, cols.reshape(shape), axis)


def _single(cols, key, fill):
    """The root of a one-root label (a first-order state's) at every speed, and the block's other
    roots: (cols without it (n_s, m - 1), its column (n_s,)).

    ``cols`` (n_s, m) are the block's columns; ``key`` the roots' pairing keys and ``fill`` the
    label's share of each root (both (n_s, n_e)). At each speed the label takes the real root
    (real key) it fills most; the others keep their places, the branch it usually takes
    standing in where it takes another (so that the pairing of real roots carried from
    speed to speed stays with the same branches).
    """
    n_s = len(cols)
    k_b, f_b = np.take_along_axis(key, cols, 1), np.take_along_axis(fill, cols, 1)
    real = np.abs(k_b.imag) <= ZERO * np.maximum(np.abs(k_b), 1e-300)
    f_b = np.where(real | ~real.any(-1, keepdims=True), f_b, -1.0)
    pick = np.argmax(f_b, axis=-1)
    usual = int(np.argmax(np.bincount(pick, minlength=cols.shape[1])))
    rest = np.delete(cols, usual, axis=1).copy()
    moved = np.flatnonzero(pick != usual)
    rest[moved, pick[moved] - (pick[moved] > usual)] = cols[moved, usual]
    return rest, cols[np.arange(n_s), pick]


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
    blocks, block = _merge_blocks(blocks, block, [own_coordinates(g, pos) for g, pos in owner])
    energy, by_order, still_group = label_content(groups, weights, eigenvalue, harmonics, orders, speeds)
    total = energy.sum(-1, keepdims=True)
    frac = energy / np.where(total > 0, total, 1.0)
    # share of each root's motion at (nearly) zero frequency
    near = np.maximum(0.25 * speeds, ZERO * np.abs(eigenvalue).max(-1))[:, None, None]  # (at rest: zero)
    at_zero = np.abs(eigenvalue.imag[..., None] + orders * speeds[:, None, None]) <= near
    still = (by_order * at_zero).sum(-1) / np.maximum(by_order.sum(-1), 1e-300)
    n_l = len(labels)
    rep = np.zeros((n_s, n_l), int)
    other = np.zeros((n_s, n_l), int)
    for blk, members in enumerate(blocks):
        cols = np.flatnonzero(block == blk)
        mine = np.array(
            [i for i, (g, pos) in enumerate(owner) if set(own_coordinates(g, pos)) <= set(members.tolist())]
        )
        singles = [i for i in mine if owner[i][0].roots == 1]
        if sum(owner[i][0].roots for i in mine) != len(cols):
            raise RuntimeError(f"block of {len(members)} coordinates has labels {[labels[i] for i in mine]}")
        cols = np.broadcast_to(cols, (n_s, len(cols)))  # (per speed: a single's root may move)
        for i in singles:
            cols, pick = _single(cols, key, frac[:, :, i])
            rep[:, i] = other[:, i] = pick
        mine = np.array([i for i in mine if i not in singles], int)
        if not len(mine):
            continue

        frac_b = _at(frac, cols)[:, :, mine]
        shapes = np.moveaxis(_at(harmonics, cols, 3) * np.sqrt(weights)[:, :, None, None], -1, 1)
        shapes = shapes.reshape(n_s, cols.shape[1], -1)  # weighted harmonics of each root
        carry = np.r_[False, speeds[:-1] > 0]
        lam_b = _at(eigenvalue, cols)
        reps, others = pair_roots(_at(key, cols), frac_b, lam_b.real, _at(still, cols), shapes, carry)
        rows = np.arange(n_s)[:, None]
        score = (frac_b[rows, reps] + frac_b[rows, others]) / 2
        real = np.maximum(lam_b[rows, reps].real, lam_b[rows, others].real)
        # (real parts and Omega: the same for every method, unlike |lambda|)
        choice = _assign(score, real, threshold, np.abs(eigenvalue.real).max(-1) + speeds + 1e-300)
        for k, g in enumerate(groups):
            if g.kind in ("cyclic", "whirl") and g.coords[0] in members:
                first = mine.tolist().index(offsets(groups)[k])
                still_k = _at(still_group[:, :, k], cols)
                share = (still_k[rows, reps] + still_k[rows, others]) / 2
                _order_still(choice, real, share, first, first + 1)
        inverse = np.argsort(choice, axis=-1)  # mode holding each label
        rep[:, mine] = np.take_along_axis(cols, np.take_along_axis(reps, inverse, -1), 1)
        other[:, mine] = np.take_along_axis(cols, np.take_along_axis(others, inverse, -1), 1)
    rows = np.arange(n_s)[:, None]
    lam, lam_other = eigenvalue[rows, rep], eigenvalue[rows, other]

    # frequencies: candidates of each label on its own root
    nr_f, nr_e, rot_f, rot_e = [], [], [], []
    for j, (g, position) in enumerate(owner):
        amp = harmonics[np.arange(n_s)[:, None], list(g.coords), :, rep[:, j : j + 1]]  # (n_s, k, M)
        cand = label_candidates(g, position, amp, weights[:, list(g.coords)], lam[:, j], orders, speeds)
        for store, value in zip((nr_f, nr_e, rot_f, rot_e), cand):
            store.append(value)
    nr_f, nr_e, rot_f, rot_e = (np.stack(x, 1) for x in (nr_f, nr_e, rot_f, rot_e))
    pick, jump = continuous_choice(nr_f, nr_e, speeds)
    pick_r, jump_r = continuous_choice(rot_f, rot_e, speeds, ratio=ROTATING_RATIO)
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
        root_eigenvalue=eigenvalue.copy(),
        harmonic_change=jump,
        harmonic_change_rotating=jump_r,
        participation=part,
        harmonics=np.moveaxis(window, -1, 2),
        harmonic_orders=np.arange(-h, h + 1),
    )


def identify_solution(solution, speeds, coords, weights, isotropic_pairs=(), threshold=None) -> Modes:
    """:func:`identify` of a tracked solution (:class:`groundres.solve.modal.Eigensolution`):
    its harmonics, or its eigenvectors as their only harmonic where it has none."""
    harmonics = solution.harmonics if solution.harmonics is not None else solution.vector[:, :, None, :]
    orders = solution.orders if solution.orders is not None else np.array([0])
    return identify(
        solution.eigenvalue,
        harmonics,
        orders,
        coords,
        weights,
        speeds,
        block=solution.block,
        blocks=solution.blocks,
        key=solution.key,
        isotropic_pairs=isotropic_pairs,
        threshold=threshold,
    )
