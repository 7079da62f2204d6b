"""The NumPy path of the transition matrices: every step's propagator formed at once.

The equations are linear, so each step's propagator is independent of the
others: for all steps and speeds of a batch the stages are formed together
from the identity, and the propagators are multiplied by pairwise reduction.
It serves while the compiled kernel (:mod:`groundres.solve.floquet.compiled`) is not ready,
with any tableau, and as the reference that kernel is tested against.
"""

from __future__ import annotations

import numpy as np

from ...model.system import System
from ..parallel import CORES, map_threads
from .coefficients import directions_of, expand, grid_nodes, node_coefficients

#: Stage values formed at once by one task (about 25 MB).
STAGE_BUDGET = 3_000_000


def ordered_product(p):
    """P[-1] @ ... @ P[1] @ P[0] over the first axis, by pairwise reduction."""
    while p.shape[0] > 1:
        if p.shape[0] % 2:
            tail = p[-1:]
            p = np.concatenate([p[1:-1:2] @ p[0:-1:2], tail])
        else:
            p = p[1::2] @ p[0::2]
    return p[0]


def _step_propagators(nodes, coef, h, tableau, tail=()):
    """One-step propagators of the Runge-Kutta method for every step and speed.

    The equation is linear, so each step's propagator P = I + h sum b_i K_i
    (stages started from the identity) is independent of the others and all
    are formed at once: arrays (steps, n_s, 2n, 2n). With y = [q; v] and
    v' = F y, a stage is K_i = [V_i; F_i Y_i]; only the lower halves
    L_i = F_i Y_i are stored, because the upper halves follow from them:
    Y_i = [I_q + h c_i I_v + h^2 sum (A^2)_il L_l ; I_v + h sum a_il L_l].
    """
    steps, stages, n, _ = nodes.shape
    n2 = 2 * n
    n_s = len(coef)
    # F at every node and speed, laid out (stages, steps, n_s, n, 2n)
    f = np.moveaxis(expand(nodes, coef, tail), 0, 2).swapaxes(0, 1)
    a, b, c = tableau.a, tableau.b, tableau.c
    a2 = a @ a
    eye_q, eye_v = np.eye(n2)[:n], np.eye(n2)[n:]
    low = np.empty((stages, steps, n_s, n, n2))
    y = np.empty((steps, n_s, n2, n2))
    for i in range(stages):
        if i == 0:
            low[0] = f[0]  # Y_1 = I
            continue
        weights = np.stack([h * h * a2[i, :i], h * a[i, :i]])
        both = np.tensordot(weights, low[:i], axes=(1, 0))  # (2, steps, n_s, n, 2n)
        y[..., :n, :] = both[0] + (eye_q + h * c[i] * eye_v)
        y[..., n:, :] = both[1] + eye_v
        np.matmul(f[i], y, out=low[i])
    weights = np.stack([h * h * (b @ a), h * b])
    both = np.tensordot(weights, low, axes=(1, 0))
    out = np.empty((steps, n_s, n2, n2))
    out[..., :n, :] = both[0] + (eye_q + h * b.sum() * eye_v)
    out[..., n:, :] = both[1] + eye_v
    return out


def plan_runs(steps: int, blocks: int, room: int) -> list:
    """Runs of at most ``room`` steps of a grid of ``steps`` split into ``blocks`` equal parts:
    [(first part, last part, [(first step, last step), ...])], whole parts where they
    are short, a long part in several pieces (to be multiplied together)."""
    room = max(1, int(room))
    per = steps // blocks
    if per <= room:
        k = max(1, room // per)
        return [(b, min(b + k, blocks), [(b * per, min(b + k, blocks) * per)]) for b in range(0, blocks, k)]
    return [
        (b, b + 1, [(s0, min(s0 + room, (b + 1) * per)) for s0 in range(b * per, (b + 1) * per, room)])
        for b in range(blocks)
    ]


def transition_pairwise(system: System, speeds, angle, steps, blocks, tableau, damping):
    """:func:`groundres.solve.floquet.transition.transition` by NumPy: every step's propagator formed
    at once, then their product.

    The work is split into tasks (threads) of a few speeds and a run of steps
    each, so that memory stays bounded however fine the grid: whole parts
    where they are short, pieces of a part multiplied together where long.
    """
    speeds = np.asarray(speeds, dtype=float)
    directions = directions_of(damping)
    tail = system.direction_halves
    coef_all = node_coefficients(speeds, damping, tail)
    h = angle / steps
    n = system.size
    n2 = 2 * n
    per = steps // blocks
    width = min(len(speeds), -(-len(speeds) // CORES))  # at least one batch per core
    room = STAGE_BUDGET // (len(tableau.c) * n * n2 * width)  # steps per task
    groups = [np.arange(i, min(i + width, len(speeds))) for i in range(0, len(speeds), width)]
    runs = plan_runs(steps, blocks, room)

    def task(item):
        sel, (b0, b1, pieces) = item
        coef = coef_all[sel]
        if len(pieces) == 1:
            nodes = grid_nodes(system, angle, steps, tableau, *pieces[0], directions)
            props = _step_propagators(nodes, coef, h, tableau, tail)  # ((b1-b0) per, k, 2n, 2n)
            return ordered_product(np.swapaxes(props.reshape((b1 - b0, per) + props.shape[1:]), 0, 1))
        out = None
        for s0, s1 in pieces:
            nodes = grid_nodes(system, angle, steps, tableau, s0, s1, directions)
            p = ordered_product(_step_propagators(nodes, coef, h, tableau, tail))
            out = p if out is None else p @ out
        return out[None]

    items = [(g, r) for g in groups for r in runs]
    done = map_threads(task, items)
    out = np.empty((blocks, len(speeds), n2, n2))
    k = 0
    for g in groups:
        for b0, b1, _ in runs:
            out[b0:b1, g[0] : g[-1] + 1] = done[k]
            k += 1
    return out
