"""Compiled propagation of transition matrices: the fast path of :mod:`groundres.solve.floquet.transition`.

The azimuth-domain equations y' = A(psi) y with A = [0 I; F(psi)] are
integrated for the transition matrix itself, one speed after another, with
the twelve stages of the Dormand-Prince eighth-order method on a fixed grid
of nodes. F at a node is a combination of a few blocks with per-speed
coefficients (1, 1/Omega, 1/Omega^2 for the inertia, damping-and-Coriolis
and spring terms; c/Omega for a damping c set per speed along a damping
direction, :mod:`groundres.solve.floquet.coefficients`), so one grid of nodes serves every speed
and every damping. Each stage costs one
product of an n x 2n block with a 2n x 2n matrix; nothing is formed twice.

Error control comes from the method's embedded estimators (the fifth- and
third-order solutions of DOP853, combined as by Hairer, Norsett and Wanner
1993, "Solving Ordinary Differential Equations I", section II.10): the
estimate of each step's local error, relative to max(1, ``|Phi|``), is summed
over the interval. No second integration is made.

NumPy's per-call overhead dominates for matrices of 10-40 states, so the
loops are compiled with numba, released from the GIL and run over batches of
speeds on groundres' thread pool (:mod:`groundres.solve.parallel`). Compiled code is
cached by numba in ``$XDG_CACHE_HOME/groundres/numba`` (``~/.cache`` by
default) only where no other account may write there (:func:`cache_folder`).
Compiling takes several seconds, more than a whole run: the first use on a
machine starts it in a background process
(:func:`kernel`) and goes on with the NumPy path (the step propagators formed
at once, step counts from a Richardson estimate: as fast as before the kernel
existed, and within the same tolerance); later runs load the compiled code
from the cache. The NumPy path is also the reference the kernel is tested
against: the same grid gives the same matrices to round-off.
"""

from __future__ import annotations

import functools
import os
import stat

import numpy as np

from ..parallel import CORES, map_threads
from .coefficients import halves as block_halves
from .tableau import DOP8_E3, DOP8_E5


def cache_folder() -> str | None:
    """The folder numba caches groundres' compiled code in, or None where it would be unsafe.

    Safe: ``groundres/numba`` under the cache root (``$XDG_CACHE_HOME`` or
    ``~/.cache``), both made by groundres with mode 0700, owned by this user
    and writable by no one else; the root itself owned by this user or root
    and writable by no other account (its group may write only where that
    group is the user's own). No other account can then plant code that this
    process would load.
    """
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    if not os.path.isabs(base):
        return None
    path = os.path.join(base, "groundres", "numba")
    uid = os.getuid()
    try:
        os.makedirs(base, mode=0o700, exist_ok=True)
        info = os.stat(base)
        shared = info.st_mode & stat.S_IWOTH or (info.st_mode & stat.S_IWGRP and info.st_gid != os.getgid())
        if info.st_uid not in (uid, 0) or shared:
            return None
        for folder in (os.path.dirname(path), path):
            try:
                os.mkdir(folder, 0o700)
                os.chmod(folder, 0o700)  # (whatever the umask)
            except FileExistsError:
                pass
            info = os.stat(folder, follow_symlinks=False)
            if not stat.S_ISDIR(info.st_mode) or info.st_uid != uid or info.st_mode & 0o022:
                return None
    except OSError:
        return None
    return path


def _propagate(nodes, coef, halves, h, a, b, e5, e3, restart, out, err):  # pragma: no cover (compiled)
    """Transition matrices over equal parts of the interval, for each speed, and error estimates.

    nodes : (steps, stages, n, B n) blocks X_b (:func:`groundres.solve.floquet.coefficients.node_blocks`);
    coef : (n_s, B); halves : (B,) the half of [q; q'] block b multiplies;
    restart : each part from the identity (else from the start of the interval);
    out : (n_s, parts, m, m) written; err : (n_s,) written: the sum over the
    steps of the embedded estimate of each step's error, relative to
    max(1, ``|Phi|``).

    The stages are kept flat, (stages, m m), so that a stage's value
    Phi + h sum_j a_ij K_j, the step's update and its two error estimates
    are each one BLAS product (numba calls SciPy's BLAS for ``np.dot``), as
    is the stage's product F Y; only F's assembly from its blocks is looped.
    """
    steps, stages, n, width = nodes.shape
    m = 2 * n
    mm = m * m
    n_b = width // n
    n_s, parts = out.shape[0], out.shape[1]
    per = steps // parts
    k = np.empty((stages, mm))
    y = np.empty((m, m))
    y_flat = y.reshape(mm)
    f = np.empty((n, m))
    fy = np.empty((n, m))
    phi = np.empty((m, m))
    phi_flat = phi.reshape(mm)
    ha = h * a
    weights = np.empty((3, stages))  # the step's update, the fifth- and third-order estimates
    for i in range(stages):
        weights[0, i] = h * b[i]
        weights[1, i] = e5[i]
        weights[2, i] = e3[i]
    combined = np.empty((3, mm))
    for s in range(n_s):
        total = 0.0
        for part in range(parts):
            if restart or part == 0:
                phi[:, :] = 0.0
                for i in range(m):
                    phi[i, i] = 1.0
            for t in range(part * per, (part + 1) * per):
                size = 1.0
                for r in range(mm):
                    size = max(size, abs(phi_flat[r]))
                for i in range(stages):
                    f[:, :] = 0.0
                    for blk in range(n_b):
                        w = coef[s, blk]
                        if w != 0.0:
                            col = halves[blk] * n
                            for r in range(n):
                                for c in range(n):
                                    f[r, col + c] += w * nodes[t, i, r, blk * n + c]
                    if i > 0:
                        np.dot(ha[i, :i], k[:i], y_flat)
                        for r in range(mm):
                            y_flat[r] += phi_flat[r]
                    else:
                        y_flat[:] = phi_flat
                    np.dot(f, y, fy)
                    for r in range(n):  # K_i = [Y_v; F Y]
                        for c in range(m):
                            k[i, r * m + c] = y[n + r, c]
                            k[i, (n + r) * m + c] = fy[r, c]
                np.dot(weights, k, combined)
                big5 = 0.0
                big3 = 0.0
                for r in range(mm):
                    phi_flat[r] += combined[0, r]
                    big5 = max(big5, abs(combined[1, r]))
                    big3 = max(big3, abs(combined[2, r]))
                big5 *= h / size
                big3 *= h / size
                if big5 > 0.0:
                    total += big5 * big5 / np.sqrt(big5 * big5 + 0.01 * big3 * big3)
            out[s, part, :, :] = phi
        err[s] = total


_KERNEL = None
_STARTED = False
_BACKGROUND = None
#: A background compilation older than this [s] is taken as dead and started again.
COMPILE_TIMEOUT = 600.0


@functools.cache
def _key() -> str:
    """What the compiled code depends on: numba's and Python's versions and this file (once a process)."""
    import hashlib
    import sys
    from importlib.metadata import version

    __version__ = version("numba")  # (without importing numba: a run that finds no kernel ready needs none)
    with open(__file__, "rb") as f:
        source = hashlib.sha256(f.read()).hexdigest()[:16]
    return f"{__version__}-py{sys.version_info[0]}{sys.version_info[1]}-{source}"


def _dispatcher(folder):
    """The kernel as a numba dispatcher, cached in ``folder`` (None: in memory only)."""
    import numba
    from numba.core import config

    previous = config.CACHE_DIR
    try:
        # numba places a function's cache when it is decorated: ours only, in a safe folder
        if folder is not None:
            config.CACHE_DIR = folder
        return numba.njit(nogil=True, cache=folder is not None)(_propagate)
    finally:
        config.CACHE_DIR = previous


def kernel(wait: bool = False):
    """The compiled kernel where it is ready, else None.

    Ready: compiled before on this machine (numba's cache in
    :func:`cache_folder` holds it), or compiled now with ``wait``. The first
    use does not wait for the compiler (several seconds): it starts it in a
    background process, which fills the cache for the runs that follow, and
    the NumPy path serves meanwhile (:func:`groundres.solve.floquet.transition.use_kernel`).
    Without a safe cache folder the kernel is compiled only with ``wait``.
    """
    global _KERNEL, _STARTED
    if _KERNEL is not None:
        return _KERNEL
    if _BACKGROUND is not None:
        _BACKGROUND.poll()
    folder = cache_folder()
    if folder is None:
        if wait:
            _KERNEL = _dispatcher(None)
        return _KERNEL
    marker = os.path.join(folder, "ready-" + _key())
    if os.path.exists(marker) or wait:
        _KERNEL = _dispatcher(folder)
        if not os.path.exists(marker):
            _warm(_KERNEL, marker)
        return _KERNEL
    if not _STARTED:
        _STARTED = True
        _compile_in_background(folder)
    return None


def _warm(dispatcher, marker):
    """Compile (or load) the kernel by one small call, then mark it ready."""
    nodes, coef = np.zeros((2, len(DOP8_E5), 1, 5)), np.ones((1, 5))
    halves = np.array([0, 1, 0, 1, 0], dtype=np.int64)
    a, b = np.zeros((len(DOP8_E5), len(DOP8_E5))), np.zeros(len(DOP8_E5))
    dispatcher(nodes, coef, halves, 0.1, a, b, DOP8_E5, DOP8_E3, True, np.empty((1, 1, 2, 2)), np.empty(1))
    with open(marker, "w") as f:
        f.write("compiled\n")


def _compile_in_background(folder):
    """Start ``python -m groundres.solve.floquet.compiled`` (the installed package compiling its
    kernel into the cache) detached, unless one started recently is still at it."""
    import subprocess
    import sys
    import time

    lock = os.path.join(folder, "compiling")
    try:
        if time.time() - os.path.getmtime(lock) < COMPILE_TIMEOUT:
            return
    except OSError:
        pass
    try:
        with open(lock, "w") as f:
            f.write(str(os.getpid()))
        global _BACKGROUND
        # (-P and the cache folder as working folder: no module is taken from wherever
        # the run was started; kept, and polled by kernel(), which reaps it)
        _BACKGROUND = subprocess.Popen(
            [sys.executable, "-P", "-m", "groundres.solve.floquet.compiled"],
            cwd=folder,
            stdin=subprocess.DEVNULL,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
            start_new_session=True,
            close_fds=True,
        )
    except OSError:  # (no process could be started: the NumPy path serves)
        pass


def compile_now():
    """Compile the kernel into the cache and mark it ready
    (``python -m groundres.solve.floquet.compiled``)."""
    folder = cache_folder()
    if folder is None:
        return
    try:
        os.nice(10)  # (in the background of the run that started it: let that run go first)
    except (AttributeError, OSError):
        pass
    try:
        _warm(_dispatcher(folder), os.path.join(folder, "ready-" + _key()))
    finally:
        try:
            os.remove(os.path.join(folder, "compiling"))
        except OSError:
            pass


def propagate(nodes, coef, h: float, tableau, parts: int = 1, cumulative: bool = False, tail=()):
    """Transition matrices over ``parts`` equal parts of a fixed grid, and their error estimates.

    Parameters
    ----------
    nodes : ndarray (steps, stages, n, B n)
        The blocks of the node matrices at the stage nodes of every step
        (:func:`groundres.solve.floquet.coefficients.node_blocks`).
    coef : ndarray (n_s, B)
        Their coefficients at each speed (:func:`groundres.solve.floquet.coefficients.node_coefficients`).
    h : float
        Step [rad].
    tableau : Tableau
        :data:`groundres.solve.floquet.tableau.DOP8` (the estimators are DOP853's).
    parts : int
        Divides the step count.
    cumulative : bool
        Transition matrices from the start of the grid to the end of each part
        instead of over each part.
    tail : tuple
        The half each direction's block multiplies
        (:func:`groundres.solve.floquet.coefficients.halves`).

    Returns
    -------
    out : ndarray (parts, n_s, 2n, 2n)
        Transition matrix of y = [q; dq/dpsi] over each part (or up to its end).
    error : ndarray (n_s,)
        Sum of the steps' estimated errors, relative to max(1, ``|Phi|``).
    """
    nodes = np.ascontiguousarray(nodes, dtype=float)
    coef = np.ascontiguousarray(coef, dtype=float)
    n_s, m = coef.shape[0], 2 * nodes.shape[-2]
    halves = np.array(block_halves(coef.shape[1], tail), dtype=np.int64)
    out = np.empty((n_s, parts, m, m))
    err = np.empty(n_s)
    compiled = kernel(wait=True)
    a, b = np.ascontiguousarray(tableau.a), np.ascontiguousarray(tableau.b)
    width = max(1, -(-n_s // CORES))
    chunks = [(i, min(i + width, n_s)) for i in range(0, n_s, width)]

    def task(chunk):
        i0, i1 = chunk
        compiled(
            nodes,
            coef[i0:i1],
            halves,
            float(h),
            a,
            b,
            DOP8_E5,
            DOP8_E3,
            not cumulative,
            out[i0:i1],
            err[i0:i1],
        )

    map_threads(task, chunks)
    return np.swapaxes(out, 0, 1), err


if __name__ == "__main__":
    compile_now()
