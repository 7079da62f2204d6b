"""The sweep as an xarray Dataset: a NetCDF round trip, then questions asked by name.

A light helicopter on skids (shipped case light-helicopter-skids: rigid body on
its gear legs, three-bladed articulated rotor, unstable during run-up). The
sweep goes to NetCDF and back unchanged (values, mode labels, units, the case
in the attributes), so it can be read later, by other tools, or compared with
another design; `groundres run` writes the same data set as modes.nc.

Run: python examples/xarray-netcdf.py [OUTPUT_DIR]
(writes sweep.nc, regressive-lag.csv and damping-ratio.png into OUTPUT_DIR, by
default groundres-out/examples/xarray-netcdf)
"""

import math
import sys
from pathlib import Path

import xarray as xr
from matplotlib.figure import Figure

import groundres

RPM = 60 / (2 * math.pi)  # rpm per rad/s

out = Path(sys.argv[1] if len(sys.argv) > 1 else "groundres-out/examples/xarray-netcdf")
out.mkdir(parents=True, exist_ok=True)

result = groundres.analyze(groundres.load_case("light-helicopter-skids"))
ds = result.to_xarray()  # dims speed [rad/s] and mode (labels); units in each variable's attrs
ds.to_netcdf(out / "sweep.nc")

with xr.open_dataset(out / "sweep.nc") as back:
    back.load()
xr.testing.assert_identical(back, ds)  # nothing lost on the way through the file
print(f"sweep.nc: {dict(back.sizes)}; modes: {', '.join(back.mode.values)}")

# Everything by name from here on: add the speed in rpm beside the SI one.
back = back.assign_coords(rpm=(back.speed * RPM).assign_attrs(units="rpm", long_name="rotor speed"))
for start, end in back.unstable_range.values:  # [rad/s], ends found by root finding
    print(f"unstable from {start * RPM:.1f} to {end * RPM:.1f} rpm")
lag = back.sel(mode="regressive lag")
peak = lag.real_part.idxmax("speed")
print(
    f"regressive lag grows fastest at {float(peak) * RPM:.0f} rpm: "
    f"{float(lag.real_part.sel(speed=peak)):.3f} {lag.real_part.units}, "
    f"at {float(lag.frequency.sel(speed=peak)) * RPM:.0f} cycles/min (nonrotating axes)"
)
operating = back.sel(speed=400 / RPM, method="nearest")  # the nominal 400 rpm
print("damping ratios at 400 rpm:", operating.damping_ratio.to_series().round(3).to_dict())

table = lag[["rpm", "frequency", "real_part", "damping_ratio"]].drop_vars("mode").to_dataframe()
table.to_csv(out / "regressive-lag.csv")  # (a pandas DataFrame: SI columns, plus rpm)

# Labels follow eigenvector content: where two modes exchange branches, their lines jump
# (the Coleman diagram, result.plot(), marks those places).
fig = Figure(figsize=(8, 4.5), layout="constrained")  # no pyplot: nothing to show, nothing to close
back.damping_ratio.plot.line(x="rpm", hue="mode", ax=fig.subplots())
fig.savefig(out / "damping-ratio.png", dpi=110)
print(f"Wrote {out}")
