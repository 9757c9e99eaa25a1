#!/usr/bin/env python
"""The explore page's warm response, measured in headless Chromium (Debian's, through Playwright).

Standalone script (not a pytest test). Run from the repository root::

    PYTHONPATH=src python benchmarks/bench_explore.py              # 10 changes of f_e, ~30 s
    PYTHONPATH=src python benchmarks/bench_explore.py --changes 20 --out FILE

``contactvib explore --no-browser`` is started in a new process; one page is opened at 0.65 Q,
360 Hz and its first search (which loads the kernels) is waited for. Then f_e is typed in turn as
361 and 360 Hz (Enter), ``--changes`` times; each response is the wall time from the key press to
the moment the page shows the attractor table of that request (the status line and the table
carry the request's number: ``data-request``). The server's own split (the search alone, and the
search with histories and the Bokeh figures) is read off the status line. Reported: median, best
and worst of each, and the load average at the start (the machine is shared); written to
``benchmarks/results_explore.json``.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import shutil
import statistics
import sys
import time
from pathlib import Path

from benchmarks import result_path


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--changes", type=int, default=10, help="number of f_e changes measured")
    ap.add_argument("--out", default=str(result_path(__name__)))
    args = ap.parse_args(argv)
    chromium = shutil.which("chromium") or shutil.which("chromium-browser")
    if chromium is None:
        sys.exit("bench_explore: no chromium binary (apt-get install chromium)")
    from playwright.sync_api import sync_playwright
    from tests.explore.test_explore_browser import _table, _wait_done, served

    load = os.getloadavg()[0]
    walls, searches, servers = [], [], []
    with served() as url, sync_playwright() as p:
        browser = p.chromium.launch(executable_path=chromium, args=["--no-sandbox"])
        page = browser.new_page(viewport={"width": 1100, "height": 1300})
        page.goto(url)
        _wait_done(page, timeout=300_000)
        assert len(_table(page)) == 5
        box = page.locator(".field-fe input")
        for i in range(args.changes):
            fe = "361" if i % 2 == 0 else "360"
            request = int(page.locator(".status .done").get_attribute("data-request"))
            box.fill(fe)
            t0 = time.perf_counter()
            box.press("Enter")
            page.locator(f'#attractors[data-request="{request + 1}"]').wait_for(timeout=60_000)
            walls.append(time.perf_counter() - t0)
            done = page.locator(f'.status .done[data-request="{request + 1}"]')
            done.wait_for(timeout=60_000)
            s, total = map(float, re.findall(r"([0-9.]+) s", done.inner_text()))
            searches.append(s)
            servers.append(total)
        browser.close()

    def stats(xs):
        return {"median_s": statistics.median(xs), "best_s": min(xs), "worst_s": max(xs)}

    res = {"point": "0.65 Q, f_e alternating 361/360 Hz", "changes": args.changes, "load_average_1min": load,
           "in_browser": stats(walls), "server_search": stats(searches), "server_total": stats(servers)}
    for name in ("in_browser", "server_search", "server_total"):
        r = res[name]
        print(f"{name:14s} median {r['median_s']:.3f} s  best {r['best_s']:.3f} s  worst {r['worst_s']:.3f} s")
    print(f"(load average at the start: {load:.2f})")
    Path(args.out).write_text(json.dumps(res, indent=1) + "\n")


if __name__ == "__main__":
    main()
