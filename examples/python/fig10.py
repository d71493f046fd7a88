"""The paper's Fig 10 from Python: the bell's angle at the first strike over
the clapping chart, ringing right and ringing wrong, with the lab bell."""

import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

import clapper

out = sys.argv[1] if len(sys.argv) > 1 else "fig10.png"
chart = clapper.chart(grid=120)  # both styles at the paper's base settings, in parallel
fig, ax = plt.subplots(figsize=(9, 6.5))
# Wrong first, right over it: where both are sustained, ringing right shows.
for style, cmap in (("wrong", "plasma"), ("right", "viridis")):
    angle = chart.values[style]["strike_angle_deg"]  # NaN where the style is not sustained
    mesh = ax.pcolormesh(chart.r_over_lc, chart.lb_over_lc, angle, cmap=cmap, shading="nearest")
    fig.colorbar(mesh, ax=ax, pad=0.02, label=f"bell angle at first strike, ringing {style} (deg)")
lab = clapper.preset("lab")
ax.plot(lab.r_over_lc, lab.lb_over_lc, "k*", markersize=14, label="the lab bell's chart position")
ax.set_xlabel("r / $L_c$")
ax.set_ylabel("$L_b$ / $L_c$")
ax.set_title("Fig 10: bell angle at the first strike (R = 0.2, from 171 deg)")
ax.legend(loc="upper left")
fig.tight_layout()
fig.savefig(out, dpi=110)
print(f"wrote {out}: {chart}")
