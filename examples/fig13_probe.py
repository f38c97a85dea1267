"""The paper's Fig. 13 in Python: the probe of silver-925, k-hat and the adaptive samples.

    python3 examples/fig13_probe.py [--out fig13.png]   # the plot needs matplotlib
"""
import argparse

import numpy as np

import specula

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--out", help="write the figure here (needs matplotlib)")
args = parser.parse_args()

probe = specula.probe("silver-925")  # theta_d 40, phi_d 90, phi_h 45 deg, 90 samples
fit = specula.fit_k(probe)  # exponential family, 30 samples
print(f"k-hat = {fit['k']:.3f} (paper: 4.78), fit error {fit['error']:.3e} 1/sr")
adaptive = np.array([np.interp(fit["theta_h_deg"], probe["theta_h_deg"], c) for c in probe["rgb"].T]).T

if args.out:
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    for ax, limit in zip(axes, (90.0, 2.0)):
        for c, colour in enumerate("rgb"):
            ax.semilogy(probe["theta_h_deg"], probe["rgb"][:, c], colour, lw=1)
            ax.semilogy(fit["theta_h_deg"], adaptive[:, c], colour + "o--", ms=3, lw=0.5)
        ax.set(xlim=(0, limit), xlabel="theta_h [deg]", ylabel="f_r [1/sr]")
    fig.suptitle(f"silver-925 probe and 30 adaptive samples, k-hat = {fit['k']:.2f}")
    fig.savefig(args.out, dpi=100)
    print(f"wrote {args.out}")
