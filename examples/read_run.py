"""Reading a finished run into numpy: summary.json, history.csv and probes.csv as tables,
and the fields of any output time as arrays.

    PYTHONPATH=build/python /usr/bin/python3 examples/read_run.py [OUTDIR]

OUTDIR: a directory written by `vpcontact run` (or vpcontact.run); without one, the
paper's 2D example is run into output/paper-2d first (n=20 unless given VPCONTACT_N).
"""
import os
import sys

import numpy as np

import vpcontact

if len(sys.argv) > 1:
    out = sys.argv[1]
else:
    out = "output/paper-2d"
    vpcontact.run(vpcontact.Case("paper-2d", n=int(os.environ.get("VPCONTACT_N", 20))), output=out)

run = vpcontact.read(out)
print(run, "- case", run.summary["case"], "- final min beta", run.summary["final"]["beta_min"])

history = run.history(frame=False)  # a structured array (frame=None: a DataFrame where pandas is installed)
print("columns:", ", ".join(history.dtype.names))
i = np.argmax(history["total_contact_force"])
print("largest contact force %.6g at t = %g" % (history["total_contact_force"][i], history["t"][i]))

print("output times:", run.times)
mid = run.fields(t=0.5 * run.times[-1])  # the output nearest T/2
last = run.fields()  # the last one
print(mid, last)
print("u at T/2: max |u| = %.6g; sigma (n_cells, 6: 11, 22, 33, 23, 13, 12):" % np.abs(mid.u).max(), mid.sigma.shape)
deformed = last.points[:, : last.u.shape[1]] + last.u
print("deformed body spans x in [%.6g, %.6g]" % (deformed[:, 0].min(), deformed[:, 0].max()))
print("nodes in contact at the end:", np.flatnonzero(last.active))

probes = run.probes(frame=False)
print("probe 0: beta from %.6g to %.6g" % (probes["p0_beta"][0], probes["p0_beta"][-1]))
