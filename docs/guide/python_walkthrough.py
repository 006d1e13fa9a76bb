# %% [markdown]
# # geardyn from Python: a walkthrough
#
# A notebook-style script (cells marked `# %%`; VS Code, Spyder and jupytext open it as a
# notebook). CI runs it end to end (`.ci/guide`), so every line here works on `main`.
# Needs `pip install './python[xarray]'` (numpy, pandas, xarray); matplotlib is optional.
#
#     python docs/guide/python_walkthrough.py [OUT_DIR]

# %%
import sys
import tempfile
import warnings
from pathlib import Path

import numpy as np

import geardyn

out = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(tempfile.mkdtemp(prefix="geardyn-"))
out.mkdir(parents=True, exist_ok=True)

# %% [markdown]
# ## 1. A model and its parameters
#
# Liu et al. 2021, Table 1, with the constant-b̄ reading of the paper's figures (R-LIU-EQ11).
# Parameters keep the Rust field names and SI units; choices are spelled as in a study file.

# %%
liu = geardyn.Liu2021(readings={"base_radius": "mean"})
print("omega1 =", liu.params["omega1"], "rad/s; readings:", liu.params["readings"])
units = {p["name"]: p["unit"] for p in geardyn.describe("liu2021")["info"]["parameters"]}
print("load_torque is in", units["load_torque"])

# %% [markdown]
# ## 2. One point
#
# Harmonic balance at 120 rad/s (below the rattle onset): a dict of numbers and numpy arrays.

# %%
r = liu.with_params(omega1=120.0).solve("hbm")
print(f"converged {r['converged']}, rsv {r['rsv']}, ppv {r['ppv']:.4g}, "
      f"{r['q'].size} samples of q over one period")
assert r["converged"] and r["rsv"] == 0

# %% [markdown]
# ## 3. A speed sweep as an xarray Dataset
#
# One dimension, `omega1`, with its unit; `rsv`, `ppv`, `reason` (why a point has no value)
# and every other scalar field of the points. `as_="pandas"` gives a DataFrame instead; the
# default (`as_="numpy"`) a dict of arrays of the shape of `omega1`.

# %%
ds = liu.rattle_sweep(np.linspace(100.0, 130.0, 7), method="hbm", as_="xarray")
print(ds)
print("units of omega1:", ds["omega1"].attrs["units"])
assert ds.sizes["omega1"] == 7

# %% [markdown]
# ## 4. A study as a DataFrame and a Dataset
#
# A 2-D map (speed × load torque) from a study file given as text (format: `docs/studies.md`).
# `to_pandas()`: one row per point, units in `df.attrs["units"]`. `to_xarray()`: the swept
# parameters are the dimensions, every output a variable with `attrs["units"]`.

# %%
study = geardyn.run_study("""
name = "guide-map"
model = "liu2021"
[overrides]
base_radius = "mean"
[sweep]
parameter = "omega1"
from = 100.0
to = 130.0
steps = 4
[sweep2]
parameter = "load_torque"
values = [20.0, 30.0, 40.0]
[solver]
method = "hbm"
""")
df = study.to_pandas()
print(df.head())
print("units:", df.attrs["units"])

m = study.to_xarray()
print(m)
assert m["ppv"].dims == ("omega1", "load_torque")
assert m["ppv"].shape == (4, 3)
print("ppv at 110 rad/s, 30 N m:", float(m["ppv"].sel(omega1=110.0, load_torque=30.0)))

# the same table indexed by the sweeps, and a CSV of it
df.set_index(df.attrs["dims"]).to_csv(out / "guide-map.csv")

# %% [markdown]
# Plots come for free where matplotlib is installed: `m.ppv.plot()` draws the map with its
# axes named after the sweeps.

# %%
try:
    import matplotlib

    matplotlib.use("Agg")
    m["ppv"].plot(x="omega1")
    import matplotlib.pyplot as plt

    plt.savefig(out / "guide-map-ppv.png")
    plt.close()
    print("wrote", out / "guide-map-ppv.png")
except ImportError:
    print("matplotlib not installed: no plot (the Dataset is complete without it)")

# %% [markdown]
# ## 5. Points that are not reliable are marked and warned about
#
# A Newton run cut short (`max_iter=1`) does not converge: the point comes back with
# `converged = False` and a `geardyn.ReliabilityWarning`. The same holds for the columns
# `settled` and `stable` where a method returns them.

# %%
with warnings.catch_warnings(record=True) as caught:
    warnings.simplefilter("always", geardyn.ReliabilityWarning)
    res = geardyn.Liu2021().sweep("omega1", [160.0], "hbm", full_r=2, max_iter=1,
                                  as_="pandas")
print(res[["omega1", "converged", "reason"]])
print("warning:", caught[0].message)
assert not res["converged"][0]
assert any(issubclass(w.category, geardyn.ReliabilityWarning) for w in caught)

print("walkthrough done; files in", out)
