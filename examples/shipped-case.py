"""Analyse shipped cases: unstable rotor speeds in rpm, the lag damping they need, Coleman diagrams.

By default the Hammond (1974) rotor on its anisotropic hub three ways: without
lag dampers (seed paper Figure 3: two unstable ranges), with all four working
(stable), and with the damper of blade 1 failed (Figure 10: Floquet analysis).

Run: python examples/shipped-case.py [OUTPUT_DIR [CASE ...]]
(CASE: a shipped case's name, see `groundres cases`, or a case file; writes
coleman-<case>.png and summary-<case>.json into OUTPUT_DIR, by default
groundres-out/examples/shipped-case)
"""

import json
import math
import sys
from pathlib import Path

import groundres

RPM = 60 / (2 * math.pi)  # rpm per rad/s: groundres works in SI, rpm is for people

out = Path(sys.argv[1] if len(sys.argv) > 1 else "groundres-out/examples/shipped-case")
names = sys.argv[2:] or ["hammond-undamped", "hammond-1974", "hammond-1974-one-damper"]
out.mkdir(parents=True, exist_ok=True)

for name in names:
    case = groundres.load_case(name)
    result = groundres.analyze(case)  # method chosen from the case: eigen or Floquet
    print(f"\n{case.title} [{result.method}]")

    # Unstable ranges [rad/s], their ends found by root finding, not tied to the sweep's spacing.
    for start, end in result.stability.unstable_ranges:
        modes = ", ".join(result.unstable_modes(start, end))
        print(f"  unstable from {start * RPM:.1f} to {end * RPM:.1f} rpm: {modes}")
    if result.stability.stable:
        print("  stable over the whole sweep")

    # Lag damping: the Deutsch criterion per body mode, then the exact minimum from the roots.
    summary = result.summary()  # what `groundres run` writes as summary.json
    lag = summary["lag_damping"]
    print(f"  installed lag damper {lag['installed']:.0f} N m s/rad, {lag['failed_dampers']} failed")
    for entry in result.deutsch:
        if entry.tuning_speed is None:
            print(f"  Deutsch, body {entry.body_mode}: no tuning, the lag mode never reaches it")
            continue
        need = entry.required_lag_damping  # inf when the body has no damping
        needs = f"needs {need:.0f} N m s/rad; " if math.isfinite(need) else ""
        print(
            f"  Deutsch, body {entry.body_mode} (tuned at {entry.tuning_speed * RPM:.0f} rpm): "
            f"{needs}{entry.reason}"
        )
    exact = lag["exact_minimum"]
    print(
        f"  exact minimum: {exact:.0f} N m s/rad"
        if exact is not None
        else f"  exact minimum: none ({lag['exact_minimum_reason']})"
    )

    stem = Path(name).stem
    result.plot().savefig(out / f"coleman-{stem}.png", dpi=110)  # a matplotlib Figure
    (out / f"summary-{stem}.json").write_text(json.dumps(summary, indent=2))

print(f"\nWrote {out}")
