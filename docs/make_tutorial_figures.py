"""Make the tutorials' figures: run the commands the tutorials show and keep the figures they write.

Usage (from the repository root; minutes on 2 cores)::

    python docs/make_tutorial_figures.py [--work DIR] [--paper DIR] [--only NAME ...]

Each entry of :data:`FIGURES` is a ``contactvib`` command line of a tutorial (at the size the page
shows, or reduced where the page's caption says so) and the figure files it writes. The figures
are copied into ``docs/_static/tutorials/`` under the entry's name, downscaled to at most
:data:`WIDTH` pixels wide and stored with a 256-colour palette (each file well under 200 KB),
and committed: the documentation build does not run the commands. ``--paper DIR`` takes the
figures of ``contactvib paper`` (and the dataset that ``contactvib map`` reads) from a finished
``contactvib paper --out DIR`` run instead of running it (about 45 s on 2 cores).
"""

from __future__ import annotations

import argparse
import contextlib
import os
import shutil
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "docs" / "_static" / "tutorials"
WIDTH = 1100
EXAMPLES = ROOT / "examples"

#: name -> (command line after ``contactvib``, {figure written, relative to the work folder or
#: a glob: the file name under docs/_static/tutorials/}). The command lines are those of the
#: tutorials; where a line is reduced, the tutorial's caption says so.
FIGURES: dict[str, tuple[list[str], dict[str, str]]] = {
    "paper": (["paper", "--out", "paper/"],
              {"paper/fig2c_pa0.65.png": "resonance_fig2c_pa0.65.png",
               "paper/fig3c_pa0.65.png": "resonance_fig3c_pa0.65.png",
               "paper/fig2e_pa0.75.png": "resonance_fig2e_pa0.75.png",
               "paper/fig4_*.png": "resonance_fig4_pa0.65_fe360.png"}),
    "simulate": (["simulate", "--pa", "0.65", "--fe", "360", "--out", "fig4/"],
                 {"fig4/*attractor1*.png": "attractors_simulate_1.png",
                  "fig4/*attractor4*.png": "attractors_simulate_4.png"}),
    "basins": (["basins", "--pa", "0.65", "--fe", "360", "--grid", "400x400", "--out", "basins/"],
               {"basins/basins_pa0.65_fe360.png": "attractors_basins.png"}),
    "section": (["section", "--pa", "0.75", "--fe", "816.5", "--impacts", "--out", "sections/section.png", "--csv",
                 "sections/section.csv"],
                {"sections/section.png": "sections_section_pa0.75_fe816.5.png"}),
    "section_chaos": (["section", "--pa", "0.75", "--fe", "816.5", "--attractor", "2", "--periods", "5000", "--impacts",
                       "--out", "sections/chaos.png"],
                      {"sections/chaos.png": "sections_section_chaotic.png"}),
    "orbit_diagram_075": (["orbit-diagram", "--pa", "0.75", "--fe-from", "808", "--fe-to", "820", "--fe-step", "0.1",
                           "--ylim", "-4", "1", "--out", "sections/od075.png"],
                          {"sections/od075.png": "sections_orbit_diagram_pa0.75.png"}),
    "orbit_diagram_080": (["orbit-diagram", "--pa", "0.8", "--fe-from", "370", "--fe-to", "445", "--fe-step", "0.25",
                           "--ylim", "-0.1", "0.4", "--out", "sections/od08.png"],
                          {"sections/od08.png": "sections_orbit_diagram_pa0.8.png"}),
    "continue": (["continue", "--pa", "0.65", "--from-fe", "1200", "--attractor", "0", "--fmin", "30", "--fmax",
                  "2000", "--out", "branch/"],
                 {"branch/branches_*.png": "continuation_branches_fe.png"}),
    "continue_pa": (["continue", "--parameter", "pa", "--pa", "0.65", "--from-fe", "360", "--pa-min", "0.05",
                     "--pa-max", "0.9", "--out", "branch_pa/"],
                    {"branch_pa/branches_*.png": "continuation_branches_pa.png"}),
    "system_continue": (["continue", "--system", str(EXAMPLES / "two_dof_stop.toml"), "--pa-newton", "0.1",
                         "--from-fe", "0.08", "--fmin", "0.08", "--fmax", "0.14", "--out", "sys_branch/"],
                        {"sys_branch/branches_*.png": "systems_continuation_two_dof.png"}),
    "perturbation": (["perturbation", "--pa", "0.65", "--fe", "287", "--terms", "40", "--out", "pert/"],
                     {"pert/perturbation_*.png": "perturbation_series_287hz.png",
                      "pert/convergence_*.png": "perturbation_convergence_287hz.png"}),
    "hbm": (["hbm", "--pa", "0.65", "--harmonics", "32", "--fmin", "300", "--fmax", "2000", "--out", "hbm/"],
            {"hbm/hbm_branch_*.png": "perturbation_hbm_branches.png"}),
    "map": (["map", "paper/", "--out", "map/"],
            {"map/map_n_attractors.png": "maps_n_attractors.png",
             "map/map_max_order.png": "maps_max_order.png"}),
    "law_exponential": (["resonance", "--pa", "0.3", "--law", "exponential", "--fmin", "300", "--fmax", "2000",
                         "--out", "res_exp/"],
                        {"res_exp/resonance_*.png": "laws_resonance_exponential.png"}),
    "random": (["simulate", "--random-psd", "1e-4", "--band", "200", "2000", "--duration", "1", "--out", "random/"],
               {"random/random_response.png": "laws_random_response.png"}),
    "fit": (["fit", "--static", str(EXAMPLES / "fit_static.csv"), "--frf", str(EXAMPLES / "fit_frf.csv"),
             "--set", "M=0.2106", "--save-model", "fitted.json", "--out", "fit/"],
            {"fit/fit_frf.png": "fitting_frf.png", "fit/fit_static.png": "fitting_static.png"}),
    "system_basins": (["basins", "--system", str(EXAMPLES / "two_dof_stop.toml"), "--pa-newton", "0.1", "--fe",
                       "0.0935", "--out", "stop_basins/"],
                      {"stop_basins/system_basins_*.png": "systems_basins_two_dof_stop.png"}),
    "system_hbm": (["hbm", "--system", str(EXAMPLES / "two_dof_stop.toml"), "--pa-newton", "0.1", "--fmin", "0.03",
                    "--fmax", "0.4", "--harmonics", "32", "--out", "hb_stop/"],
                   {"hb_stop/hbm_*.png": "systems_hbm_two_dof_stop.png"}),
    "system_resonance": (["resonance", "--system", "rocking", "--pa", "0.65", "--out", "res_rock/"],
                         {"res_rock/resonance_*.png": "systems_resonance_rocking.png"}),
    "system_atlas": (["atlas", "--system", "rocking", "--pa-min", "0.3", "--pa-max", "1.0", "--npa", "8", "--fmin",
                      "600", "--fmax", "2600", "--df", "50", "--no-progress", "--out", "atlas_rock/"], {}),
    "system_map": (["map", "atlas_rock/", "--out", "map_rock/"],
                   {"map_rock/map_max_period.png": "systems_map_max_period.png"}),
    "fit_resonance": (["resonance", "--model", "fitted.json", "--pa", "0.3", "--fmin", "900", "--fmax", "1600",
                       "--out", "res_fit/"],
                      {"res_fit/resonance_*.png": "fitting_resonance.png"}),
}


def shrink(src: Path, dst: Path) -> int:
    """Copy the PNG ``src`` to ``dst``, at most :data:`WIDTH` pixels wide, 256 colours."""
    from PIL import Image

    with Image.open(src) as im:
        im = im.convert("RGB")
        if im.width > WIDTH:
            im = im.resize((WIDTH, round(im.height * WIDTH / im.width)), Image.LANCZOS)
        im = im.quantize(colors=256, method=Image.Quantize.MEDIANCUT, dither=Image.Dither.NONE)
        im.save(dst, optimize=True)
    return dst.stat().st_size


def run(name: str, work: Path) -> None:
    from contactvib.cli.main import main

    args, figures = FIGURES[name]
    if "--no-progress" not in args and args[0] in ("resonance", "paper", "fit"):
        args = [*args, "--no-progress"]
    t0 = time.perf_counter()
    here = Path.cwd()
    os.chdir(work)
    try:
        with contextlib.redirect_stdout(sys.stderr):
            rc = main(args)
    finally:
        os.chdir(here)
    if rc:
        raise SystemExit(f"contactvib {' '.join(args)}: exit {rc}")
    print(f"{name}: contactvib {' '.join(args)} ({time.perf_counter() - t0:.0f} s)", file=sys.stderr)
    for pattern, target in figures.items():
        found = sorted(work.glob(pattern))
        if not found:
            raise SystemExit(f"{name}: no file {pattern} in {work}")
        size = shrink(found[0], OUT / target)
        print(f"  {found[0].relative_to(work)} -> {target} ({size / 1024:.0f} KB)", file=sys.stderr)


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--work", type=Path, default=Path("/tmp/contactvib-tutorial-figures"))
    parser.add_argument("--paper", type=Path, help="a finished `contactvib paper --out DIR` folder")
    parser.add_argument("--only", nargs="+", choices=list(FIGURES))
    ns = parser.parse_args(argv)
    ns.work.mkdir(parents=True, exist_ok=True)
    OUT.mkdir(parents=True, exist_ok=True)
    names = ns.only or list(FIGURES)
    if ns.paper is not None:
        dst = ns.work / "paper"
        if dst.resolve() != ns.paper.resolve():
            shutil.rmtree(dst, ignore_errors=True)
            shutil.copytree(ns.paper, dst, ignore=shutil.ignore_patterns(".chunks", ".lock"))
        names = [n for n in names if n != "paper"]
        _, figures = FIGURES["paper"]
        for pattern, target in figures.items():
            found = sorted(ns.work.glob(pattern))
            if not found:
                raise SystemExit(f"paper: no file {pattern} in {ns.paper}")
            print(f"  {found[0].relative_to(ns.work)} -> {target} ({shrink(found[0], OUT / target) / 1024:.0f} KB)",
                  file=sys.stderr)
    for name in names:
        run(name, ns.work)


if __name__ == "__main__":
    main()
