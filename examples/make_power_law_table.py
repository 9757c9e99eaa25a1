"""Write ``power_law_table.csv``: the paper's power law S c_n y^m2 sampled as a load-deflection
table (0 to 3 µm, 301 rows), the example of ``--law table`` (docs/tutorials/laws.md) and its test.

    python examples/make_power_law_table.py
"""

from pathlib import Path

import numpy as np

S, C_N, M2 = 0.0009, 4.52e16, 2.0  # the paper's (Kostek 2013, Sec. 2)

d_um = np.linspace(0.0, 3.0, 301)
load_n = S * C_N * (d_um * 1e-6) ** M2
rows = ["deflection_um,load_n"] + [f"{d:.6g},{f:.12g}" for d, f in zip(d_um, load_n)]
Path(__file__).with_name("power_law_table.csv").write_text("\n".join(rows) + "\n")
