"""The paper's 1D example (Fernandez & Sofonea 2003, Section 4) and its three figures,
Figs 4.2-4.4, from Python:  PYTHONPATH=build/python /usr/bin/python3 examples/paper_1d.py [OUTDIR]"""
import sys

import vpcontact

out = sys.argv[1] if len(sys.argv) > 1 else "output/paper-1d"
sim = vpcontact.run("paper-1d", output=out, progress=True)
print("t = %g: min beta = %.6f, contact force = %.6f" % (sim.t, sim.beta.min(), sim.contact_force.sum()))
figures = vpcontact.plot(out)  # prints them: fig_4_2_displacement_stress, fig_4_3_time_histories, fig_4_4_damage, ...
