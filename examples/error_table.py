"""An error table in a dozen lines: the accuracy harness over materials and methods, on the
paper's plan (`grid_preset="paper"`; the default is the recommended grid).

    python3 examples/error_table.py
"""
import specula

materials = ["silver-925", "green-paint", "chrome", "gold-polished", "paint-red-gloss"]
print(f"{'material':<16} {'k-hat':>6} " + " ".join(f"{m + ' rel':>11}" for m in ("linear", "log", "lobe")))
for name in materials:
    runs = {m: specula.evaluate(name, method=m, grid_preset="paper") for m in ("linear", "log", "lobe")}
    k = runs["lobe"]["k"]
    print(f"{name:<16} {k:6.3f} " + " ".join(f"{runs[m]['within']['relative_rmse']:11.4f}" for m in runs))
