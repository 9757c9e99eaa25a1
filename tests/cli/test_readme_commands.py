"""Every command line of the README and of the documentation's tutorials runs (at a reduced
size) and writes what the page says.

The command lines are read from the ```bash blocks of the README, docs/getting-started.md and
docs/tutorials/*.md (:data:`doc_pages.PAGES`), so a new line is picked up by itself:
:data:`REDUCED` must then map it to a reduced form (fewer levels, a narrower range, fewer
starts, fewer points), or :func:`test_every_readme_command_has_a_reduced_form` fails and says so.
Each reduced form keeps the README line's options otherwise, runs in-process through
:func:`contactvib.cli.main` with the working directory in a temporary folder (so ``--out X/``
writes into it, and the ``DATASET`` ``paper/paper.nc`` is the one that the reduced ``paper`` run
wrote there), and its outputs are checked: files exist, NetCDF files open with xarray and hold
the documented variables, figures are readable PNGs, JSON parses and has the documented keys.
"""

from __future__ import annotations

import contextlib
import io
import json
import os
import re
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from contactvib.cli import main
from doc_pages import PAGES, README
from figure_files import assert_figure_file


def readme_commands(text: str | None = None) -> list[str]:
    """The ``contactvib ...`` command lines of the ```bash blocks of ``text`` (default: of every
    page of :data:`doc_pages.PAGES`, each line once, in page order), without their trailing
    comments (for ``pip install . && contactvib paper``: ``contactvib paper``)."""
    if text is None:
        return list(dict.fromkeys(c for page in PAGES for c in readme_commands(page.read_text())))
    lines = []
    for block in re.findall(r"^```bash\n(.*?)^```", text, re.S | re.M):
        for line in block.splitlines():
            command = line.split("#", 1)[0].strip()
            for part in command.split("&&"):
                part = part.strip()
                if part == "contactvib" or part.startswith("contactvib "):
                    lines.append(part)
    return lines


# The sweep grid of the reduced `paper` run: 340–380 Hz at 4 Hz holds 360 Hz (the `query` line
# and Fig. 4's operating point); two multi-start frequencies with 4 starts each.
_PAPER_GRID = ["--fmin", "340", "--fmax", "380", "--df", "4", "--multistart-per-octave", "2",
               "--starts", "4", "--workers", "1", "--no-progress"]
_RESONANCE = ["resonance", "--pa", "0.6", "0.65", "--fmin", "300", "--fmax", "340", "--df", "4",
              "--multistart-per-octave", "2", "--starts", "4", "--workers", "1", "--no-progress",
              "--out", "res/"]
# The reduced atlas: two levels that hold the `query atlas/` line's point (0.6 Q, 500 Hz).
_ATLAS_GRID = ["--pa-min", "0.5", "--pa-max", "0.6", "--npa", "2", "--fmin", "490", "--fmax", "510", "--df", "10",
               "--multistart-per-octave", "1", "--starts", "2", "--no-progress"]
_ATLAS = ["atlas", *_ATLAS_GRID, "--out", "atlas/"]
#: The README's scheduler address: the test substitutes the address of a LocalCluster it starts.
_SCHEDULER = "tcp://HOST:8786"

_EXAMPLES = README.parent / "examples"
#: The reduced fit of the README's worked example: the static curve only (the FRF fit is tested
#: in tests/fit), writing fitted.json for the `resonance --model` line.
_FIT = ["fit", "--static", str(_EXAMPLES / "fit_static.csv"), "--set", "M=0.2106", "--save-model", "fitted.json",
        "--out", "fit/", "--starts", "2", "--no-progress"]
FIT_KEYS = {"parameters", "derived", "fixed", "correlation", "residual_rms", "noise", "n_forward", "time_s",
            "converged", "identifiability", "model"}

_RES_ROCK = ["resonance", "--system", "rocking", "--pa", "0.65", "--fmin", "297", "--fmax", "357", "--df", "30",
             "--starts", "2", "--no-progress", "--out", "res_rock/"]
_ATLAS_ROCK = ["atlas", "--system", "rocking", "--pa-min", "0.6", "--pa-max", "0.7", "--npa", "2", "--fmin", "600",
               "--fmax", "650", "--df", "50", "--starts", "2", "--no-progress", "--out", "atlas_rock/"]

#: README command line (comment stripped) -> the reduced argument list it is tested with.
REDUCED: dict[str, list[str]] = {
    "contactvib paper": ["paper", *_PAPER_GRID],
    "contactvib paper --out paper/": ["paper", "--out", "paper/", *_PAPER_GRID],
    "contactvib resonance --pa 0.5 0.6 0.65 0.7 0.75 0.8 0.85 0.9 --fmin 30 --fmax 2000 --df 1 --out res/":
        _RESONANCE,
    "contactvib resonance ... --resume": [*_RESONANCE, "--resume"],
    "contactvib atlas --pa-min 0.05 --pa-max 1.0 --npa 96 --fmin 30 --fmax 2000 --df 1 --out atlas/": _ATLAS,
    "contactvib atlas ... --resume": [*_ATLAS, "--resume"],
    "contactvib atlas ... --scheduler tcp://HOST:8786":
        ["atlas", *_ATLAS_GRID, "--out", "atlas_scheduler/", "--scheduler", _SCHEDULER],
    "contactvib atlas ... --dask-workers 2": ["atlas", *_ATLAS_GRID, "--out", "atlas_dask/", "--dask-workers", "2"],
    "contactvib query atlas/ --pa 0.6 --fe 500 --json": ["query", "atlas/", "--pa", "0.6", "--fe", "500", "--json"],
    "contactvib query paper/paper.nc --pa 0.65 --fe 360 --json":
        ["query", "paper/paper.nc", "--pa", "0.65", "--fe", "360", "--json"],
    "contactvib animate paper/paper.nc --out evolution.mp4":
        ["animate", "paper/paper.nc", "--out", "evolution.mp4", "--size", "320x160"],
    "contactvib animate paper/ --out evolution.gif --gif --fps 1 --size 800x400":
        ["animate", "paper/", "--out", "evolution.gif", "--gif", "--fps", "1", "--size", "320x160"],
    "contactvib attractors --pa 0.65 --fe 360":
        ["attractors", "--pa", "0.65", "--fe", "360", "--starts", "32"],
    "contactvib lyapunov --pa 0.75 --fe 816.5 --periods 20000":
        ["lyapunov", "--pa", "0.75", "--fe", "816.5", "--periods", "2000"],
    "contactvib lyapunov --pa 0.75 --fe 816.5 --y0-um -0.2008106 --v0-mm-s -4.1066862 --transient 0 --json":
        ["lyapunov", "--pa", "0.75", "--fe", "816.5", "--y0-um", "-0.2008106", "--v0-mm-s", "-4.1066862",
         "--transient", "0", "--json", "--periods", "2000"],
    "contactvib attractors --pa 0.65 --fe 360 --json":
        ["attractors", "--pa", "0.65", "--fe", "360", "--json", "--starts", "32"],
    "contactvib simulate --pa 0.65 --fe 360 --out fig4/":
        ["simulate", "--pa", "0.65", "--fe", "360", "--out", "fig4/", "--starts", "32"],
    "contactvib simulate --pa 0.9 --fe 50 --from-state 0.3 0 --periods 10 --out traj/":
        ["simulate", "--pa", "0.9", "--fe", "50", "--from-state", "0.3", "0", "--periods", "10",
         "--out", "traj/"],
    "contactvib attractors --pa 0.3 --fe 1200 --law exponential --set c_e=584 --set lam=1.413e-7":
        ["attractors", "--pa", "0.3", "--fe", "1200", "--law", "exponential", "--set", "c_e=584", "--set",
         "lam=1.413e-7", "--starts", "8", "--no-seeds"],
    "contactvib attractors --pa 0.65 --fe 360 --law table --law-file examples/power_law_table.csv":
        ["attractors", "--pa", "0.65", "--fe", "360", "--law", "table", "--law-file",
         str(README.parent / "examples" / "power_law_table.csv"), "--starts", "8", "--no-seeds"],
    "contactvib attractors --pa 0.65 --fe 360 --law clearance --set c_lin=2.037e10 --set gap_um=5":
        ["attractors", "--pa", "0.65", "--fe", "360", "--law", "clearance", "--set", "c_lin=2.037e10", "--set",
         "gap_um=5", "--starts", "8", "--no-seeds"],
    "contactvib attractors --pa 0.65 --fe 700 --damping hunt-crossley --set alpha=34.4":
        ["attractors", "--pa", "0.65", "--fe", "700", "--damping", "hunt-crossley", "--set", "alpha=34.4",
         "--starts", "8"],
    "contactvib attractors --pa 0.3 --fe 1000 --law table --law-file examples/gw_table.csv --damping hunt-crossley "
    "--set alpha=34.4":
        ["attractors", "--pa", "0.3", "--fe", "1000", "--law", "table", "--law-file",
         str(README.parent / "examples" / "gw_table.csv"), "--damping", "hunt-crossley", "--set", "alpha=34.4",
         "--starts", "8", "--no-seeds"],
    "contactvib attractors --system rocking --pa 0.65 --fe 360":
        ["attractors", "--system", "rocking", "--pa", "0.65", "--fe", "360", "--starts", "8"],
    "contactvib attractors --system rocking --pa 0.5 --fe 1300 --set e=0.01 --json":
        ["attractors", "--system", "rocking", "--pa", "0.5", "--fe", "1300", "--set", "e=0.01", "--json",
         "--starts", "24"],  # 6 of 64 starts settle (systems.md): 24 for one (an empty search exits 1)
    "contactvib simulate --system rocking --pa 0.5 --fe 1300 --set e=0.01 --from-state 0.3,2 0,0 --periods 20 "
    "--out rock/":
        ["simulate", "--system", "rocking", "--pa", "0.5", "--fe", "1300", "--set", "e=0.01", "--from-state",
         "0.3,2", "0,0", "--periods", "4", "--out", "rock/"],
    "contactvib attractors --system examples/two_dof_stop.toml --pa-newton 2 --fe 0.2":
        ["attractors", "--system", str(_EXAMPLES / "two_dof_stop.toml"), "--pa-newton", "2", "--fe", "0.2",
         "--starts", "4"],
    "contactvib simulate --system examples/two_dof_stop.toml --pa-newton 2 --fe 0.2 --out stop/":
        ["simulate", "--system", str(_EXAMPLES / "two_dof_stop.toml"), "--pa-newton", "2", "--fe", "0.2",
         "--starts", "4", "--out", "stop/"],
    "contactvib basins --system examples/two_dof_stop.toml --pa-newton 0.1 --fe 0.0935 --out stop_basins/":
        ["basins", "--system", str(_EXAMPLES / "two_dof_stop.toml"), "--pa-newton", "0.1", "--fe", "0.0935",
         "--grid", "6x5", "--starts", "16", "--out", "stop_basins/"],
    "contactvib continue --system examples/two_dof_stop.toml --pa-newton 0.1 --from-fe 0.08 --fmin 0.08 "
    "--fmax 0.14 --out sys_branch/":
        ["continue", "--system", str(_EXAMPLES / "two_dof_stop.toml"), "--pa-newton", "0.1", "--from-fe", "0.08",
         "--fmin", "0.08", "--fmax", "0.1", "--out", "sys_branch/"],
    "contactvib bifurcations --system examples/two_dof_stop.toml --pa-newton 0.1 --fmin 0.08 --fmax 0.14 "
    "--seed-fe 0.09,0.11 --out sys_bif/":
        ["bifurcations", "--system", str(_EXAMPLES / "two_dof_stop.toml"), "--pa-newton", "0.1", "--fmin", "0.08",
         "--fmax", "0.1", "--seed-fe", "0.09", "--out", "sys_bif/"],
    "contactvib hbm --system examples/two_dof_stop.toml --pa-newton 0.1 --fmin 0.03 --fmax 0.4 --harmonics 32 "
    "--out hb_stop/":
        ["hbm", "--system", str(_EXAMPLES / "two_dof_stop.toml"), "--pa-newton", "0.1", "--fmin", "0.2",
         "--fmax", "0.3", "--harmonics", "8", "--out", "hb_stop/"],
    "contactvib bifurcations --pa 0.75 --fmin 790 --fmax 830 --seed-fe 812 --cascade-fe 812 --out bif075":
        ["bifurcations", "--pa", "0.75", "--fmin", "805", "--fmax", "814", "--seed-fe", "812", "--cascade-fe",
         "812", "--max-points", "40", "--out", "bif075"],
    "contactvib attractors --system examples/two_dof_stop.toml --pa-newton 0.1 --fe 0.095 --starts 8":
        ["attractors", "--system", str(_EXAMPLES / "two_dof_stop.toml"), "--pa-newton", "0.1", "--fe", "0.095",
         "--starts", "8"],
    "contactvib attractors --system examples/self_excited_stop.toml --pa-newton 0.05 --fe 0.12 --starts 4":
        ["attractors", "--system", str(_EXAMPLES / "self_excited_stop.toml"), "--pa-newton", "0.05", "--fe", "0.12",
         "--starts", "2"],
    "contactvib attractors --pa 0.65 --fe 700 --preload 2":
        ["attractors", "--pa", "0.65", "--fe", "700", "--preload", "2", "--starts", "8"],
    "contactvib attractors --fe 1200 --base-um 0.05":
        ["attractors", "--fe", "1200", "--base-um", "0.05", "--starts", "8"],
    "contactvib attractors --fe 360 --base-g 1.5 --starts 64":
        ["attractors", "--fe", "360", "--base-g", "1.5", "--starts", "8", "--no-seeds"],
    "contactvib attractors --pa 0.3 --fe 700 --harmonic 2:0.2:90":
        ["attractors", "--pa", "0.3", "--fe", "700", "--harmonic", "2:0.2:90", "--starts", "8", "--no-seeds"],
    "contactvib resonance --pa 0.3 --law exponential --fmin 300 --fmax 2000 --out res_exp/":
        ["resonance", "--pa", "0.3", "--law", "exponential", "--fmin", "1190", "--fmax", "1210", "--df", "10",
         "--multistart-per-octave", "1", "--starts", "2", "--workers", "1", "--no-progress", "--out", "res_exp/"],
    "contactvib resonance --excitation base-um --pa 0.05 --fmin 600 --fmax 2000 --out res_base/":
        ["resonance", "--excitation", "base-um", "--pa", "0.05", "--fmin", "1100", "--fmax", "1300", "--df", "20",
         "--multistart-per-octave", "0", "--workers", "1", "--no-progress", "--out", "res_base/"],
    "contactvib continue --excitation base-um --pa 0.05 --from-fe 1200 --fmin 900 --fmax 1600 --out br_base/":
        ["continue", "--excitation", "base-um", "--pa", "0.05", "--from-fe", "1200", "--fmin", "1100",
         "--fmax", "1300", "--max-points", "20", "--out", "br_base/"],
    "contactvib simulate --random-psd 1e-4 --band 200 2000 --duration 1 --out random/":
        ["simulate", "--random-psd", "1e-4", "--band", "200", "2000", "--duration", "0.05", "--out", "random/"],
    "contactvib attractors --pa 0.5 --fe 700 --set m2=1.5 --set c_n=1e14":
        ["attractors", "--pa", "0.5", "--fe", "700", "--set", "m2=1.5", "--set", "c_n=1e14",
         "--starts", "16"],
    "contactvib section --pa 0.75 --fe 816.5 --impacts --out sections/section.png --csv sections/section.csv":
        ["section", "--pa", "0.75", "--fe", "816.5", "--impacts", "--starts", "32", "--periods", "50",
         "--out", "sections/section.png", "--csv", "sections/section.csv"],
    "contactvib section --pa 0.9 --fe 1300":
        ["section", "--pa", "0.9", "--fe", "1300", "--starts", "512", "--periods", "400"],
    "contactvib section --pa 0.75 --fe 816.5 --attractor 2 --periods 5000 --impacts --out sections/chaos.png":
        ["section", "--pa", "0.75", "--fe", "816.5", "--attractor", "0", "--periods", "50", "--impacts",
         "--starts", "16", "--out", "sections/chaos.png"],
    "contactvib orbit-diagram --pa 0.75 --fe-from 808 --fe-to 820 --fe-step 0.1 --ylim -4 1 --out sections/od075.png":
        ["orbit-diagram", "--pa", "0.75", "--fe-from", "816", "--fe-to", "817", "--fe-step", "1", "--periods", "8",
         "--starts", "16", "--ylim", "-4", "1", "--out", "sections/od075.png"],
    ("contactvib orbit-diagram --pa 0.8 --fe-from 370 --fe-to 445 --fe-step 0.25 --ylim -0.1 0.4 "
     "--out sections/od08.png"):
        ["orbit-diagram", "--pa", "0.8", "--fe-from", "420", "--fe-to", "421", "--fe-step", "1", "--periods", "8",
         "--starts", "16", "--ylim", "-0.1", "0.4", "--out", "sections/od08.png"],
    "contactvib orbit-diagram --pa 0.75 --fe-from 812 --fe-to 818 --fe-step 0.5 --out od_quick.png":
        ["orbit-diagram", "--pa", "0.75", "--fe-from", "812", "--fe-to", "813", "--fe-step", "1", "--periods", "8",
         "--starts", "16", "--out", "od_quick.png"],
    "contactvib basins --pa 0.65 --fe 360 --grid 400x400 --out basins/":
        ["basins", "--pa", "0.65", "--fe", "360", "--grid", "12x10", "--starts", "32", "--out", "basins/"],
    "contactvib basins --pa 0.65 --fe 360 --grid 60x60 --json":
        ["basins", "--pa", "0.65", "--fe", "360", "--grid", "8x6", "--starts", "32", "--json"],
    "contactvib continue --pa 0.65 --from-fe 1200 --attractor 0 --fmin 30 --fmax 2000 --out branch/":
        ["continue", "--pa", "0.65", "--from-fe", "1200", "--attractor", "0", "--fmin", "1100",
         "--fmax", "1300", "--max-points", "20", "--out", "branch/"],
    "contactvib continue --parameter pa --pa 0.65 --from-fe 360 --pa-min 0.05 --pa-max 0.9 --out branch_pa/":
        ["continue", "--parameter", "pa", "--pa", "0.65", "--from-fe", "360", "--pa-min", "0.6",
         "--pa-max", "0.7", "--max-points", "10", "--out", "branch_pa/"],
    "contactvib bifurcations --pa 0.5 0.6 0.65 0.7 0.75 0.8 0.85 0.9 --out bif/":
        ["bifurcations", "--pa", "0.6", "0.65", "--seed-fe", "1200", "--fmin", "1100", "--fmax", "1300",
         "--max-points", "20", "--out", "bif/"],
    "contactvib evolution --order 2 --pa-min 0.3 --pa-max 0.9 --out evo/":
        ["evolution", "--order", "2", "--pa-min", "0.65", "--pa-max", "0.7", "--levels", "2",
         "--out", "evo/"],
    "contactvib map paper/ --out map/": ["map", "paper/", "--out", "map/"],
    "contactvib map paper/ --curves evo/ --out map/": ["map", "paper/", "--curves", "evo/", "--out", "map/"],
    "contactvib friction --pa 0.65 --fe 360 --vd 0.1":
        ["friction", "--pa", "0.65", "--fe", "360", "--vd", "0.1", "--starts", "16"],
    "contactvib friction --pa 0.65 --fe 360 --json":
        ["friction", "--pa", "0.65", "--fe", "360", "--json", "--starts", "16"],
    "contactvib friction --pa 0.65 --fe 360 --mu 0.2 --kt-law constant --beta 0.7 --out fric/":
        ["friction", "--pa", "0.65", "--fe", "360", "--mu", "0.2", "--kt-law", "constant", "--beta", "0.7",
         "--out", "fric/", "--starts", "16"],
    "contactvib friction --pa 0.65 --fe-range 100 2000 --df 20 --starts 64 --out docs/friction/":
        ["friction", "--pa", "0.65", "--fe-range", "340", "380", "--df", "40", "--starts", "8",
         "--out", "docs/friction/"],
    "contactvib friction --pa 0.65 --fe 360 --vd-range 0.001 100 --nvd 21 --out docs/friction/":
        ["friction", "--pa", "0.65", "--fe", "360", "--vd-range", "0.001", "100", "--nvd", "3", "--starts", "8",
         "--out", "docs/friction/"],
    "contactvib friction --pa 0.65 --fe 360 --drive force --ft 0.3":
        ["friction", "--pa", "0.65", "--fe", "360", "--drive", "force", "--ft", "0.3", "--starts", "16"],
    "contactvib perturbation --pa 0.65 --fe 287 --terms 40 --out pert/":
        ["perturbation", "--pa", "0.65", "--fe", "287", "--terms", "16", "--out", "pert/"],
    "contactvib perturbation --pa 0.65 --fe 287 --terms 40 --json":
        ["perturbation", "--pa", "0.65", "--fe", "287", "--terms", "16", "--json"],
    "contactvib hbm --pa 0.65 --harmonics 32 --fmin 300 --fmax 2000 --out hbm/":
        ["hbm", "--pa", "0.65", "--harmonics", "16", "--fmin", "300", "--fmax", "340", "--out", "hbm/"],
    # fitting (docs/tutorials/fitting.md): the static curve alone, few starts
    "contactvib fit --static examples/fit_static.csv --frf examples/fit_frf.csv --set M=0.2106 "
    "--save-model fitted.json --out fit/": _FIT,
    "contactvib fit --decay examples/fit_decay.csv --set M=0.2106 --fix m2=2 --fix l=1 --json":
        ["fit", "--decay", str(_EXAMPLES / "fit_decay.csv"), "--set", "M=0.2106", "--fix", "m2=2", "--fix", "l=1",
         "--json", "--starts", "0"],
    "contactvib resonance --pa 0.65 --df 1 --friction mu=0.3,vd=0.1 --out res_fric/":
        [*_RESONANCE[:-2], "--friction", "mu=0.3,vd=0.1", "--out", "res_fric/"],
    "contactvib atlas --pa-min 0.3 --pa-max 0.9 --npa 7 --friction default --out at/":
        ["atlas", *_ATLAS_GRID, "--friction", "default", "--out", "at/"],
    "contactvib map at/ --out at/map": ["map", "at/", "--out", "at/map"],
    # the rocking unit's sweeps (docs/tutorials/systems.md): three frequencies, two levels, two starts
    "contactvib resonance --system rocking --pa 0.65 --out res_rock/": _RES_ROCK,
    "contactvib query res_rock/ --pa 0.65 --fe 1000": ["query", "res_rock/", "--pa", "0.65", "--fe", "327"],
    "contactvib atlas --system rocking --pa-min 0.3 --pa-max 1.0 --npa 8 --fmin 600 --fmax 2600 --df 50 "
    "--out atlas_rock/": _ATLAS_ROCK,
    "contactvib atlas --system rocking --pa-min 0.3 --pa-max 1.0 --npa 8 --fmin 600 --fmax 2600 --df 50 "
    "--dask-workers 2 --out atlas_rock_dask/": [*_ATLAS_ROCK[:-2], "--dask-workers", "2", "--out", "atlas_rock_dask/"],
    "contactvib map atlas_rock/ --out map_rock/": ["map", "atlas_rock/", "--out", "map_rock/"],
    "contactvib resonance --model fitted.json --pa 0.3 --fmin 900 --fmax 1600 --out res_fit/":
        ["resonance", "--model", "fitted.json", "--pa", "0.3", "--fmin", "1190", "--fmax", "1210", "--df", "10",
         "--multistart-per-octave", "1", "--starts", "2", "--workers", "1", "--no-progress", "--out", "res_fit/"],
}

#: The README lines whose reduced run is too long for the default suite (opt-in: pytest -m slow).
#: The two Dask lines: tests/sweeps/test_atlas.py runs the same atlas command with --dask-workers 2
#: and with --scheduler (a running LocalCluster) in the default suite and checks identical files.
SLOW: set[str] = {"contactvib atlas ... --dask-workers 2", "contactvib atlas ... --scheduler tcp://HOST:8786"}

#: README lines that start a server (they never return, so they have no reduced run here): each
#: is driven in headless Chromium by tests/explore/test_explore_browser.py (the dataset ones by
#: test_explore_dataset_browser.py; a folder as `atlas/` by test_explore_dataset.py; the
#: --graph-* grid by test_explore_level_graph_browser.py; the law options by
#: test_explore_law.py, with the server replaced by a stub) instead.
SERVERS: set[str] = {"contactvib explore", "contactvib explore --port 8765 --no-browser",
                     "contactvib explore paper/paper.nc", "contactvib explore atlas/",
                     "contactvib explore --graph-fmin 100 --graph-fmax 1000 --graph-df 2",
                     "contactvib explore --law exponential --preload 2",
                     "contactvib explore at/"}  # its friction panel: tests/friction/test_friction_views.py

# ------------------------------------------------------------------ documented contents

#: `attractors --json` (docs/formats.md, "JSON contract").
ATTRACTORS_KEYS = {"fn0_hz", "y0_um", "pa_over_q", "fe_hz", "n_box", "n_seeds", "n_failed", "units",
                   "attractors"}
ATTRACTOR_KEYS = {"period", "minima_per_period", "app_um", "ymin_um", "ymax_um", "loses_contact",
                  "contact_loss_fraction", "basin_fraction", "floquet_abs_max", "floquet_multipliers",
                  "closure", "hits", "strobe_points", "extrema", "dofs", "contacts"}
#: `query --json`: the attractors contract plus the dataset's labels (docs/formats.md, "Dataset layout");
#: the dataset stores no start counts and no `hits`.
QUERY_TOP_KEYS = {"fn0_hz", "y0_um", "pa_over_q", "fe_hz", "requested", "units", "attractors"}
QUERY_KEYS = (ATTRACTOR_KEYS - {"hits"}) | {"resonance", "branch", "branch_label", "attractor_type",
                               "lyapunov_per_period", "found_by", "reached_by_sweep", "origin"}
#: The resonance dataset (`paper.nc`, `resonance.nc`), docs/formats.md "Dataset layout".
DATASET_VARS = {"pa_over_q", "fe_hz", "kind", "period", "minima_per_period", "app_um", "ymin_um",
                "ymax_um", "loses_contact", "contact_loss_fraction", "basin_fraction", "floquet_re",
                "floquet_im", "floquet_abs_max", "closure", "lyapunov_per_period", "attractor_type",
                "dominant_harmonic", "resonance", "branch_index", "origin", "found_by", "state_y_um",
                "state_ydot_mm_s", "harmonics_um", "extrema_start", "extrema_count", "strobe_start",
                "strobe_count", "extremum_t_ms", "extremum_y_um", "extremum_is_min", "strobe_y_um",
                "strobe_ydot_mm_s", "branch_id", "branch_label", "branch_pa_over_q", "branch_period",
                "branch_minima", "branch_fmin_hz", "branch_fmax_hz", "branch_npoints",
                "branch_app_max_um", "branch_reached_by_sweep", "trace_label", "trace_root",
                "trace_direction", "trace_f_start_hz", "trace_f_stop_hz", "trace_stop", "dof_name", "dof_unit",
                "dof_min", "dof_max", "dof_app", "dof_h1", "contact_name", "contact_loses_contact",
                "contact_loss_frac", "contact_mean_force_n"}
DATASET_ATTRS = {"model", "settings", "fn0_hz", "y0_um", "levels_pa_over_q"}
#: A branch file `branch_<id>.nc` (docs/tutorials/continuation.md).
BRANCH_VARS = {"fe_hz", "pa_over_q", "app_um", "ymin_um", "ymax_um", "floquet_re", "floquet_im",
               "stable", "state_x", "state_xdot", "minima_per_period", "contact_loss_fraction",
               "arclength"}
#: A system's branch file (docs/tutorials/systems.md).
SYSTEM_BRANCH_VARS = {"fe_hz", "pa_newton", "pa_over_q", "app", "qmin", "qmax", "contact_loss_fraction",
                      "floquet_re", "floquet_im", "stable", "state", "arclength"}
#: `continue/bifurcations --json` and `special_points_<tag>.json`.
SPECIAL_KEYS = {"type", "fe_hz", "pa_over_q", "app_um", "period", "branch"}
STOP_KEYS = {"fe_hz", "pa_over_q", "reason", "branch"}
#: `basins --json`: each entry of "fractions" (docs/tutorials/attractors.md, "Basins").
BASIN_FRACTION_KEYS = {"label", "period", "minima_per_period", "app_um", "fraction", "stderr"}
#: `perturbation --json`.
PERTURBATION_KEYS = {"app_um", "ymin_um", "ymax_um", "valid", "terms", "error_estimate", "fe_hz",
                     "pa_over_q", "harmonics_um", "reason", "summation"}


def _dataset(path: Path, levels) -> None:
    with xr.open_dataset(path) as d:
        assert DATASET_VARS <= set(d.variables), sorted(DATASET_VARS - set(d.variables))
        assert DATASET_ATTRS <= set(d.attrs), sorted(DATASET_ATTRS - set(d.attrs))
        assert sorted({round(float(p), 6) for p in d["pa_over_q"].values}) == sorted(levels)
        assert d.sizes["point"] > 0 and d.sizes["branch"] > 0


def _figures(folder: Path, pattern: str, at_least: int = 1) -> list[Path]:
    pngs = sorted(folder.glob(pattern))
    assert len(pngs) >= at_least, (folder, pattern, [p.name for p in folder.iterdir()])
    for p in pngs:
        assert_figure_file(p)
    return pngs


def _special_points_json(d: dict) -> None:
    assert set(d) >= {"special_points", "stops"}
    assert d["stops"], "every direction of every branch ends with a stop"
    for s in d["special_points"]:
        assert SPECIAL_KEYS <= set(s) and s["type"] in {"fold", "period-doubling", "neimark-sacker", "grazing"}
    for s in d["stops"]:
        assert STOP_KEYS <= set(s) and s["reason"]


def _branches(folder: Path, tag: str) -> None:
    files = sorted(folder.glob("branch_*.nc"))
    assert files, [p.name for p in folder.iterdir()]
    for f in files:
        with xr.open_dataset(f) as b:
            assert BRANCH_VARS <= set(b.variables), (f.name, sorted(BRANCH_VARS - set(b.variables)))
            assert b.sizes[next(iter(b["app_um"].dims))] >= 1
    _special_points_json(json.loads((folder / f"special_points_{tag}.json").read_text()))
    assert_figure_file(folder / f"branches_{tag}.png")


def _attractors_json(d: dict, pa: float, fe: float) -> None:
    assert ATTRACTORS_KEYS <= set(d), sorted(ATTRACTORS_KEYS - set(d))
    assert d["pa_over_q"] == pytest.approx(pa) and d["fe_hz"] == pytest.approx(fe)
    atts = d["attractors"]
    assert atts and [a["app_um"] for a in atts] == sorted((a["app_um"] for a in atts), reverse=True)
    for a in atts:
        assert ATTRACTOR_KEYS <= set(a), sorted(ATTRACTOR_KEYS - set(a))


# ------------------------------------------------------------------ checks, one per README line

def _check_paper(out: Path, stdout: str) -> None:
    _dataset(out / "paper.nc", [0.5, 0.6, 0.65, 0.7, 0.75, 0.8, 0.85, 0.9])
    assert not (out / ".chunks").exists() and not (out / ".lock").exists()  # a complete run tidies up
    _figures(out, "fig2?_pa*.png", 8)
    _figures(out, "fig3?_pa*.png", 8)
    assert (out / "fig2a_pa0.50.png").is_file() and (out / "fig3h_pa0.90.png").is_file()
    _figures(out, "fig4_*.png", 1)  # 360 Hz, 0.65 Q lies on the reduced grid
    index = (out / "index.md").read_text()
    assert "fig2a_pa0.50.png" in index and "S3." in index
    assert "wrote" in stdout and "paper.nc" in stdout


def _check_resonance(out: Path, stdout: str) -> None:
    _dataset(out / "resonance.nc", [0.6, 0.65])
    assert not (out / ".chunks").exists() and not (out / ".lock").exists()  # a complete run tidies up
    for p in ("0.60", "0.65"):
        assert_figure_file(out / f"resonance_pa{p}.png")
        assert_figure_file(out / f"extrema_pa{p}.png")
    assert "2 levels" in stdout


def _friction_columns(path: Path, friction: bool) -> None:
    """A dataset holds the friction columns (docs/tutorials/friction.md) exactly when made with ``--friction``."""
    with xr.open_dataset(path) as d:
        assert ("friction_ratio" in d) == friction and ("friction" in d.attrs) == friction
        if friction:
            ratio = d["friction_ratio"].values
            assert d["friction_ratio"].attrs["units"] == "1" and (ratio[ratio == ratio] <= 1.0 + 1e-9).all()
            assert (ratio == ratio).sum() >= 1  # periodic points carry a ratio


def _check_atlas(out: Path, stdout: str) -> None:
    _dataset(out / "atlas.nc", [0.5, 0.6])
    assert not (out / ".chunks").exists()  # a complete run removes its resume data
    with xr.open_dataset(out / "atlas.nc") as d:
        assert d["app_um"].encoding["zlib"] and d["app_um"].encoding["complevel"] == 4
    assert "2 levels" in stdout and "atlas.nc" in stdout


def _atlas_run(workdir: Path, capsys) -> Path:
    """The reduced ``atlas --out atlas/`` (run once in the module's working directory)."""
    if not (workdir / "atlas" / "atlas.nc").is_file():
        _run(_ATLAS, workdir, capsys)
    return workdir / "atlas"


@pytest.fixture(scope="module")
def dask_scheduler():
    """The address of a running Dask scheduler (a LocalCluster of one worker process), for the
    README's ``--scheduler tcp://HOST:8786`` line."""
    from distributed import LocalCluster

    with LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        yield cluster.scheduler_address


def _check_map(folder: Path, stdout: str, curves: bool) -> None:
    """`map` (README, "Regime maps"): map.nc over the reduced paper run's grid, one figure per map."""
    names = ("n_attractors", "max_order", "contact_loss_share", "chaotic", "max_period")
    for name in names:
        assert_figure_file(folder / f"map_{name}.png")
    with xr.open_dataset(folder / "map.nc") as m, xr.open_dataset(folder.parent / "paper" / "paper.nc") as ds:
        assert dict(m["n_attractors"].sizes) == {"pa_over_q": 8, "fe_hz": 11}
        assert set(names) <= set(m.data_vars) and int(m["n_attractors"].sum()) == ds.sizes["point"]
        assert ("curve_fe_hz" in m and m.sizes["curve"] >= 1) == curves
    assert "8 levels x 11 frequencies" in stdout and ("fold crossings" in stdout) == curves


def _check_query(stdout: str, pa: float = 0.65, fe: float = 360.0) -> None:
    d = json.loads(stdout)
    assert d["pa_over_q"] == pytest.approx(pa) and d["fe_hz"] == pytest.approx(fe)
    assert QUERY_TOP_KEYS <= set(d), sorted(QUERY_TOP_KEYS - set(d))
    assert d["requested"]
    assert d["attractors"]
    for a in d["attractors"]:
        assert QUERY_KEYS <= set(a), sorted(QUERY_KEYS - set(a))


def _check_system_sweep(args: list[str], stdout: str, workdir: Path) -> None:
    """``resonance``/``atlas --system rocking``, and ``query``/``map`` of their datasets."""
    from contactvib.sweeps.stored import open_resonance

    if args[0] == "query":
        assert "system rocking" in stdout and "theta A_pp [urad]" in stdout
        return
    folder = workdir / args[args.index("--out") + 1]
    if args[0] == "map":
        for name in ("n_attractors", "contact_loss_share", "max_period"):
            assert_figure_file(folder / f"map_{name}.png")
        return
    name = "resonance.nc" if args[0] == "resonance" else "atlas.nc"
    with open_resonance(folder / name) as data:
        assert data.ds.attrs["system"] == "rocking" and data.ds.sizes["dof"] == 2 and data.ds.sizes["point"] >= 1
        assert data.levels == ((0.65,) if args[0] == "resonance" else (0.6, 0.7))
    assert "attractor points" in stdout
    if args[0] == "resonance":
        assert_figure_file(folder / "resonance_0.65Q_y_theta_app.png")
    elif "--dask-workers" in args:
        assert xr.load_dataset(folder / name).identical(xr.load_dataset(workdir / "atlas_rock" / name))


def _check_system(args: list[str], stdout: str, folder: Path | None) -> None:
    """``--system``: the JSON's attractors with their ``dofs`` and ``contacts``, the table's header,
    or the figures of ``simulate`` (a pair per trajectory or attractor)."""
    if "--json" in args:
        d = json.loads(stdout)
        assert {"natural_frequencies_hz", "n_unsettled", "attractors"} <= set(d)
        for a in d["attractors"]:
            assert {"period", "floquet_multipliers", "stable", "basin_fraction", "dofs", "contacts"} <= set(a)
    elif args[0] == "basins":  # docs/tutorials/systems.md: the table, the labels' dataset, the figure
        assert stdout.startswith("system ") and "q1 in [" in stdout and "fraction" in stdout
        with xr.open_dataset(folder / "system_basins.nc") as b:
            assert b["label"].shape == (5, 6) and b["a"].attrs["units"] == "um" and b.attrs["slice"] == "q1,q1_dot"
        _figures(folder, "system_basins_*.png", 1)
    elif args[0] == "attractors":
        assert stdout.startswith("system ") and "linear modes:" in stdout
        if any(a.endswith("self_excited_stop.toml") for a in args):  # docs/tutorials/systems.md: a torus
            assert stdout.splitlines()[3].split()[1] == "q-per" and "quasi-periodic" in stdout
    elif args[0] == "bifurcations":  # docs/tutorials/systems.md: every branch, each followed once
        d = json.loads((folder / "bifurcations.json").read_text())
        assert d["stops"] and d["cascades"] == [] and "neimark-sacker" in {sp["type"] for sp in d["special_points"]}
        for sp in d["special_points"]:
            assert {"type", "fe_hz", "pa_newton", "period", "branch", "floquet_multipliers", "dofs",
                    "contacts"} <= set(sp)
        _figures(folder, "branches_*.png", 1)
    elif args[0] == "hbm":  # docs/tutorials/systems.md: the HB branch with its multipliers
        d = json.loads((folder / "branch.json").read_text())
        assert d["coordinates"] == ["q1", "q2"] and d["harmonics"] == 8 and d["points"]
        assert {"fe_hz", "stable", "floquet_multipliers", "dofs", "contacts"} <= set(d["points"][0])
        _figures(folder, "hbm_*_q1_app.png", 1)
    elif args[0] == "continue":  # docs/tutorials/systems.md: the branch file, special points, figure
        (nc,) = folder.glob("branch_b0_*.nc")
        with xr.open_dataset(nc) as b:
            assert SYSTEM_BRANCH_VARS <= set(b.variables), sorted(SYSTEM_BRANCH_VARS - set(b.variables))
        (js,) = folder.glob("special_points_*.json")
        sps = json.loads(js.read_text())["special_points"]
        assert "neimark-sacker" in {sp["type"] for sp in sps}
        for sp in sps:
            assert {"type", "fe_hz", "pa_newton", "period", "branch", "floquet_multipliers", "dofs",
                    "contacts"} <= set(sp)
        _figures(folder, "branches_*.png", 1)
        assert "neimark-sacker" in stdout and "wrote 1 branch files" in stdout
    else:
        pngs = _figures(folder, "*.png", 2)
        assert len(pngs) % 2 == 0 and len(list(folder.glob("*_forces.png"))) == len(pngs) // 2
        if "--from-state" not in args:
            assert len(json.loads((folder / "attractors.json").read_text())["attractors"]) == len(pngs) // 2


def _check_attractors_table(stdout: str, pa: float | None, fe: float, law: str | None = None) -> None:
    """The table's header (P_a, or the base motion when ``pa`` is None), the model line of a law
    other than the paper's (naming ``law``), the column heads and a first row."""
    lines = stdout.splitlines()
    first = f"P_a = {pa:g} Q (" if pa is not None else "base motion "
    assert lines[0].startswith(first) and f"f_e = {fe:g} Hz" in lines[0]
    if law is not None:
        assert lines[1].startswith("model: ") and law in lines[1]
        lines = lines[1:]
    assert lines[1].split()[:3] == ["#", "period", "minima"]
    assert len(lines) >= 3 and lines[2].split()[0] == "0"


# ------------------------------------------------------------------ the runs

@pytest.fixture(scope="module")
def workdir(tmp_path_factory):
    """The working directory of every run (``--out X/`` and ``paper/paper.nc`` are relative)."""
    return tmp_path_factory.mktemp("readme")


def _run(args: list[str], workdir: Path, capsys) -> str:
    old = os.getcwd()
    os.chdir(workdir)
    try:
        capsys.readouterr()
        rc = main(list(args))
        captured = capsys.readouterr()
    finally:
        os.chdir(old)
    assert rc == 0, (args, captured.err)
    return captured.out


@pytest.fixture(scope="module")
def paper_run(workdir):
    """The reduced ``contactvib paper --out paper/``: the DATASET of the ``query`` line."""
    old = os.getcwd()
    os.chdir(workdir)
    buf = io.StringIO()
    try:
        with contextlib.redirect_stdout(buf):
            rc = main(REDUCED["contactvib paper --out paper/"])
    finally:
        os.chdir(old)
    assert rc == 0
    return buf.getvalue()


def test_readme_commands_are_found():
    cmds = readme_commands()
    assert "contactvib paper" in cmds  # from `pip install . && contactvib paper`
    assert len(cmds) >= 15
    # each tutorial page is read: its commands are among the tested lines
    tutorials = [p for p in PAGES if p.parent.name == "tutorials" and p.name != "index.md"]  # the index lists them
    assert len(tutorials) >= 9
    for page in tutorials:
        own = readme_commands(page.read_text())
        assert own and set(own) <= set(cmds), page.name
    text = "```bash\npip install . && contactvib paper   # x\ncontactvib a --b 1\n```\n```\ncontactvib no\n```\n"
    assert readme_commands(text) == ["contactvib paper", "contactvib a --b 1"]


def test_documented_names_are_on_the_formats_page():
    """The keys and variables these tests check are the ones docs/formats.md documents."""
    text = (PAGES[0].parent / "docs" / "formats.md").read_text()
    names = ATTRACTORS_KEYS | ATTRACTOR_KEYS | QUERY_TOP_KEYS | QUERY_KEYS | DATASET_VARS | DATASET_ATTRS
    missing = sorted(n for n in names if f"`{n}`" not in text and f'"{n}"' not in text)
    assert not missing, f"docs/formats.md does not name: {missing}"


def _uncovered(commands: list[str]) -> str:
    """The failure message for README command lines that have no reduced form ('' if none)."""
    missing = [c for c in commands if c not in REDUCED and c not in SERVERS]
    return ("" if not missing else "README command lines without a reduced form: add each to "
            f"REDUCED in tests/cli/test_readme_commands.py (and its output check): {missing}")


def test_a_new_readme_line_without_a_reduced_form_is_reported():
    text = README.read_text() + "\n```bash\ncontactvib attractors --pa 0.7 --fe 400\n```\n"
    msg = _uncovered(readme_commands(text))
    assert "add each to REDUCED" in msg and "'contactvib attractors --pa 0.7 --fe 400'" in msg


def test_every_readme_command_has_a_reduced_form():
    msg = _uncovered(readme_commands())
    assert not msg, msg
    stale = [c for c in [*REDUCED, *SERVERS] if c not in readme_commands()]
    assert not stale, f"REDUCED names lines that are no longer in the README: {stale}"


def _params():
    return [pytest.param(c, marks=pytest.mark.slow, id=c) if c in SLOW else pytest.param(c, id=c)
            for c in REDUCED]


@pytest.mark.parametrize("line", _params())
def test_readme_command_runs_and_writes_its_outputs(line, workdir, request, capsys):
    args = REDUCED[line]
    if "paper/" in line:  # the line writes or reads the module's dataset run
        paper_run = request.getfixturevalue("paper_run")
    # the reduced form keeps the command and the README's output folder
    assert args[0] == line.split()[1]
    m = re.search(r"--out (\S+)", line)
    if m:
        assert args[args.index("--out") + 1] == m.group(1)
    if line == "contactvib paper --out paper/":  # the module's dataset run
        _check_paper(workdir / "paper", paper_run)
        return
    if line == "contactvib resonance ... --resume":
        # the chunks of a run stopped after its sweeps (kept: --keep-chunks), 0.6 Q's marked so
        # that the resumed dataset shows it was reused, not recomputed
        # (in a folder of its own: res/ stays the dataset of the other lines)
        res = workdir / "res_resume"
        own = [*args[:args.index("--out")], "--out", "res_resume/", *args[args.index("--out") + 2:]]
        _run([*own, "--keep-chunks"], workdir, capsys)
        chunk = res / ".chunks" / "level_pa0.6.nc"
        marked = xr.load_dataset(chunk)
        marked["app_um"] = marked["app_um"] + 1.0
        marked.to_netcdf(chunk)
        (res / "resonance.nc").unlink()
        out = _run(own, workdir, capsys)
        stored = xr.load_dataset(res / "resonance.nc")
        at = np.flatnonzero(stored["pa_over_q"].values == 0.6)
        assert np.array_equal(stored["app_um"].values[at], marked["app_um"].values)
        _check_resonance(res, out)
        return
    if line.startswith("contactvib atlas ... ") or line.startswith("contactvib query atlas/"):
        atlas = _atlas_run(workdir, capsys)
        chunks = {p: p.stat().st_mtime_ns for p in (atlas / ".chunks").glob("level_pa*.nc")}
        if _SCHEDULER in args:
            args = [request.getfixturevalue("dask_scheduler") if a == _SCHEDULER else a for a in args]
        out = _run(args, workdir, capsys)
        if args[0] == "query":
            _check_query(out, 0.6, 500.0)
            return
        folder = workdir / args[args.index("--out") + 1]
        _check_atlas(folder, out)
        if "--resume" in args:
            assert {p: p.stat().st_mtime_ns for p in (atlas / ".chunks").glob("level_pa*.nc")} == chunks
        assert xr.load_dataset(folder / "atlas.nc").identical(xr.load_dataset(atlas / "atlas.nc"))
        return
    if line == "contactvib paper":  # the default folder, paper/, in a folder of its own
        sub = workdir / "default"
        sub.mkdir(exist_ok=True)
        out = _run(args, sub, capsys)
        _check_paper(sub / "paper", out)
        return
    if "--curves" in args and not (workdir / "evo" / "evolution_order2.json").is_file():
        _run(REDUCED["contactvib evolution --order 2 --pa-min 0.3 --pa-max 0.9 --out evo/"], workdir, capsys)
    if "--model" in args and not (workdir / "fitted.json").is_file():
        _run(_FIT, workdir, capsys)
    # the lines that read the rocking unit's resonance.nc or atlas.nc (or compare with it) run it first
    first = {"res_rock/": _RES_ROCK, "atlas_rock/": _ATLAS_ROCK, "atlas_rock_dask/": _ATLAS_ROCK}
    for token, run_first in first.items():
        if token in args and args != run_first and not (workdir / run_first[-1]).is_dir():
            _run(run_first, workdir, capsys)
    out = _run(args, workdir, capsys)
    if (args[0] in ("resonance", "atlas") and "--system" in args) or (args[0] in ("query", "map")
                                                                      and "_rock" in args[1]):
        # the rocking unit's sweeps, their query and map
        _check_system_sweep(args, out, workdir)
        return
    cmd = args[0]
    folder = workdir / m.group(1) if m else None
    if cmd == "fit" and "--json" in args:
        d = json.loads(out)
        assert FIT_KEYS <= set(d) and set(d["parameters"]) == {"S_c_n", "S_h_n", "y_init_um", "v_init_mm_s",
                                                                  "f_n0_hz", "y0_um", "zeta"}
        assert d["fixed"]["m2"] == 2.0 and {"f_n0_hz", "y0_um", "zeta"} <= set(d["derived"])
    elif cmd == "fit":
        d = json.loads((folder / "fit.json").read_text())
        assert FIT_KEYS <= set(d) and {"S_c_n", "m2"} <= set(d["parameters"])
        assert_figure_file(folder / "fit_static.png")
        from contactvib import ContactModel

        assert ContactModel(**json.loads((workdir / "fitted.json").read_text())).m2 == d["parameters"]["m2"]["value"]
        assert "wrote" in out and "S_c_n" in out
    elif cmd == "resonance" and "--model" in args:  # the fitted contact's resonance graph
        with xr.open_dataset(folder / "resonance.nc") as d:
            model = json.loads(d.attrs["model"])
            assert model["m2"] == json.loads((workdir / "fitted.json").read_text())["m2"] and d.sizes["point"] >= 1
        assert_figure_file(folder / "resonance_pa0.30.png")
    elif cmd == "resonance" and "--law" in args:  # another law: its name and parameters in the dataset
        with xr.open_dataset(folder / "resonance.nc") as d:
            assert "exponential" in d.attrs["law"] and json.loads(d.attrs["model"])["law"] == "exponential"
            assert d.sizes["point"] >= 1
        assert_figure_file(folder / "resonance_pa0.30.png")
    elif cmd == "resonance" and "--excitation" in args:  # levels of base displacement U [um]
        with xr.open_dataset(folder / "resonance.nc") as d:
            assert d.attrs["excitation"] == "base-um" and d["pa_over_q"].attrs["units"] == "um"
            assert d.sizes["point"] >= 1
        assert_figure_file(folder / "resonance_U0.05um.png")
        assert "attractor points" in out
    elif cmd == "resonance":
        _check_resonance(folder, out)
        _friction_columns(folder / "resonance.nc", "--friction" in args)
    elif cmd == "atlas":
        _check_atlas(folder, out)
        _friction_columns(folder / "atlas.nc", "--friction" in args)
    elif cmd == "map" and args[1] == "at/":  # the friction atlas's maps
        with xr.open_dataset(folder / "map.nc") as m:
            assert {"friction_ratio_min", "friction_ratio_max"} <= set(m.data_vars)
            assert float(m["friction_ratio_min"].min()) >= 0.0 and float(m["friction_ratio_max"].max()) <= 1.0 + 1e-9
        for name in ("friction_ratio_min", "friction_ratio_max"):
            assert_figure_file(folder / f"map_{name}.png")
    elif cmd == "query":
        _check_query(out)
    elif cmd == "animate" and "--gif" in args:  # one frame per level of the reduced paper run
        import imageio.v3 as iio

        assert iio.improps(folder, plugin="pillow").shape == (8, 160, 320, 3) and "8 frames" in out
        assert iio.immeta(folder, plugin="pillow", index=0)["duration"] == 1000
    elif cmd == "animate":  # one frame per level of the reduced paper run, at the declared size and rate
        import imageio_ffmpeg

        assert imageio_ffmpeg.count_frames_and_secs(str(folder))[0] == 8
        meta = next(imageio_ffmpeg.read_frames(str(folder)))
        assert meta["size"] == (320, 160) and meta["fps"] == pytest.approx(2.0) and "8 frames" in out
    elif cmd == "simulate" and "--random-psd" in args:
        assert_figure_file(folder / "random_response.png")
        with xr.open_dataset(folder / "random.nc") as d:
            assert d.sizes[next(iter(d["y_um"].dims))] > 100
    elif "--system" in args:
        _check_system(args, out, folder)
    elif cmd == "section" and "--pa" in args and args[args.index("--pa") + 1] == "0.9":
        assert_figure_file(workdir / "section_pa0.9_fe1300.png")
        assert "chaotic" not in out and "period 12" in out and "period 72" in out
    elif cmd == "section" and "--attractor" in args:
        assert_figure_file(workdir / m.group(1))
        assert len(out.splitlines()) == 4 and out.splitlines()[2].split()[0] == "0"
    elif cmd == "section":
        assert_figure_file(workdir / m.group(1))
        lines = (workdir / "sections" / "section.csv").read_text().splitlines()
        assert "units" in lines[1] and lines[2].startswith("attractor,kind,map,period,k,y_um") and len(lines) > 3
    elif cmd == "orbit-diagram":
        assert_figure_file(workdir / m.group(1))
        assert "grid points" in out
    elif cmd == "attractors" and "--json" in args:
        _attractors_json(json.loads(out), 0.65, 360.0)
    elif cmd == "attractors":
        pa = float(args[args.index("--pa") + 1]) if "--pa" in args else None
        fe = float(args[args.index("--fe") + 1])
        law = "law" if any(o in args for o in ("--law", "--damping", "--preload", "--set")) else None
        _check_attractors_table(out, pa, fe, law)
    elif cmd == "basins" and "--json" in args:
        d = json.loads(out)
        assert d["pa_over_q"] == pytest.approx(0.65) and d["fe_hz"] == pytest.approx(360.0)
        assert d["grid"] == [8, 6] and d["fractions"][-1]["label"] == -1
        for r in d["fractions"]:
            assert set(r) == BASIN_FRACTION_KEYS
    elif cmd == "basins":
        assert_figure_file(folder / "basins_pa0.65_fe360.png")
        with xr.open_dataset(folder / "basins.nc") as b:
            assert b["label"].shape == (10, 12) and {"fraction", "stderr", "app_um"} <= set(b.variables)
        assert "wrote" in out
    elif cmd == "simulate" and "--from-state" in args:
        assert_figure_file(folder / "trajectory_pa0.9_fe50.png")
    elif cmd == "simulate":
        pngs = _figures(folder, "*.png", 1)
        d = json.loads((folder / "attractors.json").read_text())
        _attractors_json(d, 0.65, 360.0)
        assert len(d["attractors"]) == len(pngs)
    elif cmd == "continue" and "--parameter" in args:
        _branches(folder, "pa0.65_fe360_in_pa")
        for f in folder.glob("branch_*.nc"):
            with xr.open_dataset(f) as b:
                assert float(b["pa_over_q"].min()) >= 0.6 - 1e-9 and float(b["pa_over_q"].max()) <= 0.7 + 1e-9
    elif cmd == "continue" and "--excitation" in args:
        _branches(folder, "U0.05_fe1200")
        for f in folder.glob("branch_*.nc"):
            with xr.open_dataset(f) as b:
                assert b["pa_over_q"].attrs["units"] == "um" and float(b["pa_over_q"].max()) == 0.05
    elif cmd == "continue":
        _branches(folder, "pa0.65_fe1200")
    elif cmd == "bifurcations" and "--cascade-fe" in args:  # docs/tutorials/cascades.md
        d = json.loads((folder / "bifurcations.json").read_text())
        (c,) = d["cascades"]
        assert c["periods"][0] == 10 and c["pd_fe_hz"][0] == pytest.approx(813.4029, abs=1e-3)
        assert "cascade: periods 10" in out
    elif cmd == "bifurcations":
        _branches(folder, "pa0.6")
        _branches(folder, "pa0.65")
        _special_points_json(json.loads((folder / "bifurcations.json").read_text()))
    elif cmd == "evolution":
        d = json.loads((folder / "evolution_order2.json").read_text())
        assert {"order", "levels_pa_over_q", "curves", "points", "extremes"} <= set(d)
        assert d["order"] == 2 and len(d["levels_pa_over_q"]) == 2
        assert d["curves"] and d["points"]  # the 1/2's fold curve at least, and its folds
        for c in d["curves"]:
            assert {"type", "fe_hz", "pa_over_q", "stops"} <= set(c) and c["type"] in {"fold", "period-doubling"}
        for sp in d["points"]:
            assert SPECIAL_KEYS <= set(sp)
        for onset in d["extremes"].values():
            assert {"fe_hz", "pa_over_q"} <= set(onset)
        assert_figure_file(folder / "evolution_order2.png")
    elif cmd == "map":
        _check_map(folder, out, "--curves" in args)
    elif cmd == "perturbation" and "--json" in args:
        d = json.loads(out)
        assert PERTURBATION_KEYS <= set(d), sorted(PERTURBATION_KEYS - set(d))
        assert d["fe_hz"] == 287.0 and d["terms"] == 16
    elif cmd == "perturbation":
        _figures(folder, "perturbation_*.png", 1)
        _figures(folder, "convergence_*.png", 1)
        (csv,) = folder.glob("convergence_*.csv")
        rows = csv.read_text().splitlines()
        assert rows[0].split(",")[:2] == ["terms", "app_plain_um"] and len(rows) >= 3
        assert int(rows[-1].split(",")[0]) == 16  # numbers of terms up to --terms
    elif cmd == "hbm":
        _figures(folder, "hbm_branch_*.png", 1)
        d = json.loads((folder / "branch.json").read_text())
        assert {"pa_over_q", "harmonics", "fmin_hz", "fmax_hz", "branches"} <= set(d)
        assert d["harmonics"] == 16 and (d["fmin_hz"], d["fmax_hz"]) == (300.0, 340.0) and d["branches"]
    elif cmd == "friction":
        _check_friction(args, folder, out)
    elif cmd == "lyapunov" and "--json" in args:  # one trajectory on the chaotic attractor
        s = json.loads(out)["spectra"][0]
        assert s["attractor_type"] == "chaotic" and s["lyapunov_per_s"][0] > 3 * s["lyapunov_stderr_per_s"][0]
    elif cmd == "lyapunov":  # one row per attractor: Floquet exponents, Benettin's for the chaotic one
        rows = out.splitlines()[1:]
        assert "exponents [1/s]" in out.splitlines()[0] and len(rows) >= 4
        assert sum("chaotic" in r and "benettin" in r for r in rows) == 1
    else:
        raise AssertionError(f"no output check for {line!r}: add one to this test")


def _check_friction(args, folder, out):
    """`friction`: the table or JSON of one point, its time histories, or a grid's CSV and figure."""
    if "--json" in args:
        d = json.loads(out)
        assert d["attractors"] and all(0.0 < a["friction_ratio"] < 1.0 for a in d["attractors"])
    elif "--fe-range" in args or "--vd-range" in args:
        stem = "friction_fe" if "--fe-range" in args else "friction_vd"
        assert (folder / f"{stem}.csv").read_text().startswith("fe_hz,vd_mm_s,attractor")
        assert_figure_file(folder / f"{stem}.png")
    else:
        assert out.splitlines()[1].split()[:2] == ["#", "period"] and len(out.splitlines()) >= 3
        if folder is not None:
            assert_figure_file(folder / "friction_0.png")
            assert json.loads((folder / "friction.json").read_text())
