"""Write examples/gw_table.csv: a Greenwood–Williamson rough contact (Gaussian summit heights,
sigma = 0.5 um, summit radius 50 um, 1e8 summits per m^2, E* = 115 GPa, the paper's nominal area
S = 0.0009 m^2) tabulated on 400 rows up to 2 um, for `--law table --law-file`. With Hunt-Crossley
damping alpha = 34.4 s/m and the paper's mass it gives y0 = 0.31 um, f_n0 = 1456 Hz, zeta = 0.018.

    python examples/make_gw_table.py
"""

from pathlib import Path

from contactvib.model.greenwood_williamson import GreenwoodWilliamson

gw = GreenwoodWilliamson(sigma=0.5e-6, radius=50e-6, density=1e8, e_star=1.15e11)
table = gw.table(area=0.0009, y_max=2e-6, n=400)
out = Path(__file__).with_name("gw_table.csv")
out.write_text("deflection_um,load_n\n" + "".join(
    f"{float(d) * 1e6!r},{float(f)!r}\n" for d, f in zip(table.deflection_m, table.load_n)))
print(f"wrote {out} ({table.deflection_m.size} rows, {table.source})")
