"""The sweep as tidy rows for pandas: one row per speed and mode, in the case's unit.

Columns: ``speed`` (the case's ``[sweep] unit``), ``mode`` (the label),
``frequency`` (the result's frame, in the case's frequency unit: cycles/min
for an rpm case), ``real_part`` [1/s], ``damping_ratio`` [-] and
``vibrating`` (whether the mode counts for the margins there:
:func:`groundres.assess.margins.vibrating`). ``DataFrame.attrs`` holds the
units, the frame, the method and the case's title.
"""

from __future__ import annotations

import numpy as np

from ..model.units import FREQUENCY_UNITS, SPEED_UNITS


def to_dataframe(result):
    """A :class:`pandas.DataFrame` of the sweep, one row per (speed, mode)."""
    import pandas as pd

    unit = result.case.sweep.unit
    per = SPEED_UNITS[unit]
    n_s, n_m = result.frequency.shape
    vibrating = result.margins.vibrating if result.margins is not None else np.ones((n_s, n_m), bool)
    frame = pd.DataFrame(
        {
            "speed": np.repeat(np.asarray(result.rotor_speed, float) / per, n_m),
            "mode": pd.Categorical(np.tile(result.labels, n_s), categories=result.labels),
            "frequency": (result.frequency / per).ravel(),
            "real_part": result.real_part.ravel(),
            "damping_ratio": result.damping_ratio.ravel(),
            "vibrating": vibrating.ravel(),
        }
    )
    frame.attrs = {
        "units": {
            "speed": unit,
            "frequency": FREQUENCY_UNITS[unit],
            "real_part": "1/s",
            "damping_ratio": "1",
        },
        "frame": result.frame,
        "method": str(result.method),
        "title": result.case.title,
    }
    return frame
