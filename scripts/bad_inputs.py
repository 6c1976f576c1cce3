#!/usr/bin/python3
"""Runs `vpcontact check` (or `run`) on bad inputs and prints the table of docs/reliability.md
("Bad inputs"): each input, what is wrong with it, the exit code and the message.

  /usr/bin/python3 scripts/bad_inputs.py build/app/vpcontact > /tmp/bad-inputs.md
  /usr/bin/python3 scripts/bad_inputs.py build/app/vpcontact --doc docs/reliability.md           # fail if stale
  /usr/bin/python3 scripts/bad_inputs.py build/app/vpcontact --doc docs/reliability.md --update  # regenerate

The test reliability.bad_inputs runs the second form, so the table cannot go stale unnoticed.

Every input is written to a fresh temporary folder (file names in the messages
are relative to it). The script fails if an input is accepted, if vpcontact
dies by a signal (exit code > 127), or if a sanitizer reports anything (run it
with build-asan/app/vpcontact too).
"""
import os
import pathlib
import re
import resource
import subprocess
import sys
import tempfile

CASE = """[mesh]
generator = "rectangle"
lower = [0.0, 0.0]
upper = [2.0, 1.0]
cells = [8, 4]

[[mesh.part]]
name = "patch"
where = "abs(y) < 1e-9 && x > 0.5 && x < 1.5"

[boundary]
clamped = "top"
contact = "patch"

[elasticity]
kind = "plane-stress"
E = 100.0
nu = 0.3

[viscoplasticity]
law = "perzyna"
lambda = 10.0
sigma_y = 0.5

[damage]
kappa = 1.0
source = "von-mises"
beta0 = 1.0

[loads]
f0 = ["0", "-10*t"]

[contact]
gap = "0.001*x"

[time]
T = 1.0
steps = 10

[output]
probes = [[1.0, 0.0]]
"""

MESH_CASE = """[mesh]
file = "{mesh}"

[boundary]
clamped = "clamped"
contact = "contact"

[elasticity]
kind = "plane-stress"
E = 100.0
nu = 0.3

[time]
steps = 2
"""

SQUARE_MSH = """$MeshFormat
2.2 0 8
$EndMeshFormat
$PhysicalNames
3
1 1 "contact"
1 2 "clamped"
2 3 "body"
$EndPhysicalNames
$Nodes
4
1 0 0 0
2 1 0 0
3 1 1 0
4 0 1 0
$EndNodes
$Elements
4
1 1 2 1 1 1 2
2 1 2 2 3 3 4
3 2 2 3 1 1 2 3
4 2 2 3 1 1 3 4
$EndElements
"""

# Found by fuzz_gmsh_msh: Gmsh 4.8.4 (and the gmsh program) crash on it (SIGSEGV).
GMSH_CRASH = '$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n2\n4 3 "body"'

SQUARE_GEO = """Point(1) = {0, 0, 0, 0.5}; Point(2) = {1, 0, 0, 0.5};
Point(3) = {1, 1, 0, 0.5}; Point(4) = {0, 1, 0, 0.5};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
"""


# The reporter's inputs of issue 26 (tests/data/reported/, copies of ../shared/reported/).
REPORTED = pathlib.Path(__file__).resolve().parent.parent / "tests" / "data" / "reported"


def reported(*names):
    return {name: (REPORTED / name).read_bytes() for name in names}


def case(frm, to):
    assert frm in CASE, frm
    return CASE.replace(frm, to, 1)


# (what is wrong, {file name: content}, arguments of `vpcontact check`[, options]); options:
# {"address_space": bytes} runs the command under that RLIMIT_AS; {"warning": True}: the input is
# accepted (exit 0) with a warning, which must be on stderr; {"first": [...]}: a command run first,
# which must succeed (a run to resume); {"elide": [(regex, text)]}: parts of the message that depend
# on the machine (the free space of a disk), replaced in the table.
INPUTS = [
    # --- case files
    ("not a TOML file (binary)", {"c.toml": b"\x7fELF\x02\x01\x01\x00\x00"}, ["c.toml"]),
    ("unclosed array", {"c.toml": case("upper = [2.0, 1.0]", "upper = [2.0, 1.0")}, ["c.toml"]),
    ("a section twice", {"c.toml": case("[time]", "[time]\n[time]")}, ["c.toml"]),
    ("table header without a name", {"c.toml": "[=]\n" + CASE}, ["c.toml"]),
    ("non-ASCII character in a key", {"c.toml": case("kappa = 1.0", "kappaé = 1.0")}, ["c.toml"]),
    ("misspelt section", {"c.toml": case("[damage]", "[damge]")}, ["c.toml"]),
    ("misspelt key", {"c.toml": case("kappa = 1.0", "kapa = 1.0")}, ["c.toml"]),
    ("wrong type", {"c.toml": case("E = 100.0", 'E = "hundred"')}, ["c.toml"]),
    ("Poisson's ratio out of range", {"c.toml": case("nu = 0.3", "nu = 0.5")}, ["c.toml"]),
    ("infinite number", {"c.toml": case("upper = [2.0, 1.0]", "upper = [inf, 1.0]")}, ["c.toml"]),
    ("NaN", {"c.toml": case('gap = "0.001*x"', "gap = nan")}, ["c.toml"]),
    ("unknown value", {"c.toml": case('kind = "plane-stress"', 'kind = "plane-stres"')}, ["c.toml"]),
    ("missing section", {"c.toml": CASE.split("[boundary]")[0] + "[elasticity]" + CASE.split("[elasticity]")[1]},
     ["c.toml"]),
    ("no cells", {"c.toml": case("cells = [8, 4]", "cells = [8, 0]")}, ["c.toml"]),
    ("fractional cells", {"c.toml": case("cells = [8, 4]", "cells = [8.5, 4]")}, ["c.toml"]),
    ("mesh too large", {"c.toml": case("cells = [8, 4]", "cells = [100000, 100000]")}, ["c.toml"]),
    ("upper corner below lower", {"c.toml": case("upper = [2.0, 1.0]", "upper = [2.0, -1.0]")}, ["c.toml"]),
    ("boundary part that does not exist", {"c.toml": case('contact = "patch"', 'contact = "pach"')}, ["c.toml"]),
    ("part predicate selecting nothing", {"c.toml": case("x > 0.5 && x < 1.5", "x > 5")}, ["c.toml"]),
    ("unknown variable in a formula", {"c.toml": case('gap = "0.001*x"', 'gap = "0.001*q"')}, ["c.toml"]),
    ("formula syntax error", {"c.toml": case('f0 = ["0", "-10*t"]', 'f0 = ["0", "-10*(t"]')}, ["c.toml"]),
    ("formula of the wrong length", {"c.toml": case('f0 = ["0", "-10*t"]', 'f0 = ["-10*t"]')}, ["c.toml"]),
    ("negative gap", {"c.toml": case('gap = "0.001*x"', 'gap = "-0.001*x"')}, ["c.toml"]),
    ("initial damage outside [0, 1]", {"c.toml": case("beta0 = 1.0", 'beta0 = "1 + x"')}, ["c.toml"]),
    ("misspelt law", {"c.toml": case('law = "perzyna"', 'law = "perzina"')}, ["c.toml"]),
    ("misspelt law parameter", {"c.toml": case("lambda = 10.0", "lamda = 10.0")}, ["c.toml"]),
    ("both source and phi", {"c.toml": case('source = "von-mises"', 'source = "von-mises"\nphi = "-vm"')}, ["c.toml"]),
    ("time step not dividing T", {"c.toml": case("steps = 10", "dt = 0.3")}, ["c.toml"]),
    ("both steps and dt", {"c.toml": case("steps = 10", "steps = 10\ndt = 0.1")}, ["c.toml"]),
    ("probe of the wrong dimension", {"c.toml": case("probes = [[1.0, 0.0]]", "probes = [[1.0]]")}, ["c.toml"]),
    ("output time after T", {"c.toml": case("probes = [[1.0, 0.0]]", "times = [2.0]")}, ["c.toml"]),
    # --- mesh files
    ("mesh file missing", {"c.toml": MESH_CASE.format(mesh="body.msh")}, ["c.toml"]),
    ("mesh file is a folder", {"c.toml": MESH_CASE.format(mesh="."), "d/x": ""}, ["c.toml"]),
    ("refine a negative number of times", {"c.toml": MESH_CASE.format(mesh="body.msh"), "body.msh": SQUARE_MSH},
     ["c.toml", "--set", "mesh.refine=-1"]),
    ("refine a generated mesh", {"c.toml": CASE}, ["c.toml", "--set", "mesh.refine=2"]),
    ("refine a mesh beyond 3e7 cells", {}, ["dome-3d", "--set", "mesh.refine=5"]),
    ("refine a mesh beyond the numbers of a mesh (2^31 cells)", {}, ["dome-3d", "--set", "mesh.refine=9"]),
    ("not a mesh", {"c.toml": MESH_CASE.format(mesh="body.msh"), "body.msh": "this is { not a mesh ;;\n"},
     ["c.toml"]),
    ("truncated .msh", {"c.toml": MESH_CASE.format(mesh="body.msh"),
                        "body.msh": "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 2\nxx\n"}, ["c.toml"]),
    ("malformed .msh that crashes Gmsh 4.8", {"c.toml": MESH_CASE.format(mesh="body.msh"),
     "body.msh": GMSH_CRASH}, ["c.toml"]),
    ("element refers to an undefined node", {"c.toml": MESH_CASE.format(mesh="body.msh"),
     "body.msh": SQUARE_MSH.replace("3 2 2 3 1 1 2 3", "3 2 2 3 1 1 2 7")}, ["c.toml"]),
    ("degenerate element", {"c.toml": MESH_CASE.format(mesh="body.msh"),
     "body.msh": SQUARE_MSH.replace("4 0 1 0\n", "4 2 2 0\n")}, ["c.toml"]),
    ("quadrilaterals", {"c.toml": MESH_CASE.format(mesh="body.geo"),
     "body.geo": SQUARE_GEO + "Transfinite Surface{1}; Recombine Surface{1};\n"}, ["c.toml"]),
    ("2D mesh off the plane z = 0", {"c.toml": MESH_CASE.format(mesh="body.msh"),
     "body.msh": SQUARE_MSH.replace("3 1 1 0\n", "3 1 1 0.5\n")}, ["c.toml"]),
    ("physical groups only (no domain elements saved)", {"c.toml": MESH_CASE.format(mesh="body.msh"),
     "body.msh": SQUARE_MSH.replace("4\n1 1 2 1 1 1 2", "2\n1 1 2 1 1 1 2").split("3 2 2 3")[0] + "$EndElements\n"},
     ["c.toml"]),
    ("facet in two physical groups", {"c.toml": MESH_CASE.format(mesh="body.msh"),
     "body.msh": SQUARE_MSH.replace("4\n1 1 2 1 1 1 2", "5\n1 1 2 1 1 1 2\n5 1 2 2 1 1 2")}, ["c.toml"]),
    ("physical group with no such part name", {"c.toml": MESH_CASE.format(mesh="body.msh").replace(
        'contact = "contact"', 'contact = "bottom"'), "body.msh": SQUARE_MSH}, ["c.toml"]),
    (".geo script that calls Exit", {"c.toml": MESH_CASE.format(mesh="body.geo"), "body.geo": SQUARE_GEO + "Exit;\n"},
     ["c.toml"]),
    # --- command line
    ("case file that does not exist", {}, ["nothere.toml"]),
    ("unknown built-in case", {}, ["paper-9d"]),
    ("unknown option", {}, ["paper-1d", "--frobnicate"]),
    ("negative time step", {}, ["paper-1d", "--dt", "-0.01"]),
    ("zero steps", {}, ["paper-1d", "--steps", "0"]),
    ("negative kappa", {}, ["paper-2d", "--kappa", "-1"]),
    ("option value not a number", {}, ["paper-1d", "--steps", "ten"]),
    ("unknown solver", {}, ["paper-1d", "--contact-solver", "magic"]),
    ("--set without =", {}, ["paper-1d", "--set", "damage.kappa"]),
    ("--set with a blank key", {}, ["paper-1d", "--set", " =1"]),
    ("--set of a misspelt key", {}, ["paper-2d", "--set", "damage.kapa=1"]),
    ("--set of a too large mesh", {}, ["paper-2d", "--set", "mesh.cells=[100000,100000]"]),
    ("mesh size that misses the contact patch's ends", {}, ["paper-2d", "--n", "12"]),
    # --- issue 11: command line (item 10)
    ("misspelt option (--verison)", {}, ["run", "paper-1d", "--verison"]),
    ("subcommand misspelt", {}, ["rnu", "paper-1d"]),
    ("cases --show of an unknown case", {}, ["cases", "--show", "paper-9d"]),
    ("plot in an unknown format", {"out/x": ""}, ["plot", "out", "--format", "bmp"]),
    # --- --set that conflicts with itself; --n on a Gmsh case (item 11)
    ("--set of both steps and dt", {}, ["paper-1d", "--set", "time.steps=10", "--set", "time.dt=0.1"]),
    ("--n on a case that reads a Gmsh mesh", {}, ["dome-3d", "--n", "4"]),
    # --- output directory (item 9): checked before set-up, with the OS's reason
    ("output directory that cannot be created", {}, ["run", "block-3d", "--n", "40", "-o", "/proc/vpc"]),
    ("output directory below a file", {"afile": "x"}, ["run", "paper-1d", "-o", "afile/out"]),
    # --- a directory name a shell would run (item 1): figures drawn, nothing run; the
    # input is bad only in that --resume names a directory without checkpoints
    ("--resume DIR where DIR is a shell command (nothing is run)", {"x'; touch INJECTED; echo '/y": ""},
     ["run", "paper-1d", "--resume", "x'; touch INJECTED; echo '", "--plot"]),
    # --- sizes (issue 11 items 2, 3): refused before allocating or factorizing, never a crash
    ("--n far too large for a built-in case", {}, ["run", "block-3d", "--n", "100000", "-o", "out"]),
    ("--n too large for a 2D built-in case", {}, ["paper-2d", "--n", "5000"]),
    ("estimated memory above --memory-limit (with --engine auto the run goes on with CG + GAMG instead)", {}, ["block-3d", "--n", "20", "--memory-limit", "50M", "--engine", "serial"]),
    ("--memory-limit that is not a size", {}, ["paper-1d", "--memory-limit", "lots"]),
    ("CHOLMOD runs out of memory (address space limited to 460 MB)", {},
     ["block-3d", "--n", "20", "--memory-limit", "unlimited"], {"address_space": 460_000_000}),
    # --- contact data (items 4, 12)
    ("contact direction pointing into the body", {"c.toml": case('gap = "0.001*x"', 'gap = "0.001*x"\ndirection = [0, 1]')},
     ["c.toml"]),
    ("gap formula that is not finite", {"c.toml": case('gap = "0.001*x"', 'gap = "sqrt(x - 10)"')}, ["c.toml"]),
    # --- at run time
    ("--resume from a folder without checkpoints", {"empty/x": ""},
     ["run", "paper-1d", "--resume", "empty", "--no-vtu"]),
    ("--retry-halvings out of range", {}, ["run", "paper-1d", "--retry-halvings", "50", "-o", "out"]),
    ("formula for phi that gives NaN during the run", {"c.toml": case('source = "von-mises"',
     'phi = "t > 0.45 ? sqrt(-1) : -vm/100"')}, ["run", "c.toml", "--no-vtu", "-o", "out"]),
    # --- issue 26: wrong answers that were reported as success, and hostile inputs
    ("explicit viscoplastic step beyond its stability bound (Perzyna)", {},
     ["run", "paper-2d", "--n", "10", "--set", "viscoplasticity.law=perzyna", "--set", "viscoplasticity.lambda=1.0",
      "--set", "viscoplasticity.sigma_y=2.0", "--steps", "100", "--no-vtu", "-o", "out"]),
    ("explicit viscoplastic step beyond its stability bound (maxwell-damage)", {},
     ["run", "paper-2d", "--n", "10", "--set", "viscoplasticity.law=maxwell-damage", "--set",
      "viscoplasticity.rate=1000", "--set", "damage.c=1", "--steps", "100", "--no-vtu", "-o", "out"]),
    ("plane obstacle whose normal points away from the body", reported("plane_normal_away.toml"),
     ["plane_normal_away.toml"]),
    ("obstacle position that is NaN at t = 0.5", reported("obstacle_nan.toml"),
     ["run", "obstacle_nan.toml", "--no-vtu", "-o", "out"]),
    ("valid: every free node is a contact node (2D, one cell)", reported("thin.toml"),
     ["run", "thin.toml", "--no-vtu", "-o", "out"], {"valid": True}),
    ("valid: every free node is a contact node (3D, one layer)", reported("thin3d.toml"),
     ["run", "thin3d.toml", "--no-vtu", "-o", "out"], {"valid": True}),
    ("coordinates of size 1e120", reported("huge_coords.toml", "huge_coords.msh"),
     ["run", "huge_coords.toml", "--no-vtu", "-o", "out"]),
    ("numerically singular damage matrix (kappa = 1e300)", {},
     ["run", "paper-1d", "--set", "damage.kappa=1e300", "--no-vtu", "-o", "out"]),
    ("probe outside the body", reported("probe_outside.toml"), ["probe_outside.toml"]),
    ("Poisson's ratio 0.4999999999 in plane strain with P1 elements (locking)",
     {"c.toml": case("nu = 0.3", "nu = 0.4999999999").replace('"plane-stress"', '"plane-strain"')},
     ["c.toml"], {"warning": True}),
    (".geo that runs a shell command (SystemCall)", reported("syscall.toml", "syscall.geo"), ["syscall.toml"]),
    ("case file that is a FIFO", {"c.toml": None}, ["c.toml"]),
    ("a .geo loop that does not end ([mesh] time_limit = 2)", {"c.toml": MESH_CASE.format(mesh="body.geo").replace(
        "[boundary]", "time_limit = 2\n\n[boundary]"), "body.geo": SQUARE_GEO + "For i In {1:1e15}\nEndFor\n"},
     ["c.toml"]),
    ("case.name that leaves the output folder", {"c.toml": CASE},
     ["run", "c.toml", "--set", "case.name=../../escaped", "--no-vtu"]),
    ("a 300,000-character case name", {"c.toml": "[case]\nname = \"" + "n" * 300_000 + "\"\n" + CASE},
     ["c.toml"]),
    ("a 1 MB formula", {"c.toml": case('gap = "0.001*x"', 'gap = "0.001*x' + " + x" * 200_000 + ' + q"')},
     ["c.toml"]),
    ("control characters (ESC, BEL) in a string", {"c.toml": case('contact = "patch"', 'contact = "\\u001b[31mpatch\\u0007"')},
     ["c.toml"]),    ("Coulomb friction coefficient below 0", {}, ["shear-2d", "--set", "contact.mu=-0.3"]),
    ("friction coefficient without friction = \"coulomb\"", {"c.toml": case('gap = "0.001*x"', 'gap = "0.001*x"\nmu = 0.3')},
     ["c.toml"]),
    # --- issue 48: --resume with a changed case (steps 1-10 of one problem, the rest of another),
    # and an output that would not fit on the disk
    ("--resume with another E than the checkpoint's", reported("resume_changed_law.toml"),
     ["run", "resume_changed_law.toml", "-o", "out", "--no-vtu", "--set", "elasticity.E=2000", "--resume", "out"],
     {"first": ["run", "resume_changed_law.toml", "-o", "out", "--no-vtu", "--set", "time.T=1.0", "--steps", "10"]}),
    ("--resume with another friction coefficient mu", reported("resume_changed_law.toml"),
     ["run", "resume_changed_law.toml", "-o", "out", "--no-vtu", "--set", "contact.mu=0.6", "--resume", "out"],
     {"first": ["run", "resume_changed_law.toml", "-o", "out", "--no-vtu", "--set", "time.T=1.0", "--steps", "10"]}),
    ("--resume with another Tresca bound", reported("resume_changed_law.toml"),
     ["run", "resume_changed_law.toml", "-o", "out", "--no-vtu", "--set", "contact.friction=tresca", "--set",
      "contact.friction_bound=5", "--resume", "out"],
     {"first": ["run", "resume_changed_law.toml", "-o", "out", "--no-vtu", "--set", "time.T=1.0", "--steps", "10",
                "--set", "contact.friction=tresca", "--set", "contact.friction_bound=1"]}),
    ("10^8 steps with a VTU file at each: an output beyond the disk's free space",
     reported("resume_changed_law.toml"), ["resume_changed_law.toml", "--steps", "100000000", "--set", "output.every=1"],
     {"elide": [(r"the [0-9.]+ [KMGTPE]?i?B free", "the (free space) free")]}),
    ("Tresca bound that is NaN for t > 0.5",
     {"c.toml": case('gap = "0.001*x"', 'gap = "0.001*x"\nfriction = "tresca"\nfriction_bound = "t > 0.5 ? sqrt(-1) : 1"')},
     ["run", "c.toml", "--no-vtu", "-o", "out"]),
    # Issue 48: Coulomb's shear limit, a traction > 0; Tresca acting out of contact warns.
    ("shear limit of 0", {}, ["shear-2d", "--set", "contact.shear_limit=0"]),
    ("shear limit that is a formula < 0 on part of the face", {}, ["shear-2d", "--set", "contact.shear_limit=\"x\""]),
    ("shear limit with friction = \"tresca\"", {},
     ["shear-2d", "--set", "contact.friction=\"tresca\"", "--set", "contact.friction_bound=1", "--set",
      "contact.shear_limit=1"]),
    ("Tresca friction through nodes not in contact (a plane 0.1 away that slides)", {},
     ["run", "shear-2d", "--no-vtu", "-q", "-o", "out", "--set", "contact.friction=\"tresca\"", "--set",
      "contact.friction_bound=1", "--set", "obstacle[0].point=[\"0.02*max(t - 1, 0)\", \"-0.1\"]"],
     {"warning": True}),
    ("a component prescribed twice with different values (two [[boundary.displacement]] tables)",
     {"c.toml": case('clamped = "top"\ncontact = "patch"',
                     'contact = "patch"\n\n[[boundary.displacement]]\nparts = "top"\nux = 0\nuy = "-0.01*t"\n\n'
                     '[[boundary.displacement]]\nparts = "right"\nuy = 0')}, ["c.toml"]),
    ("a pressure on a contact part",
     {"c.toml": case('f0 = ["0", "-10*t"]', 'f0 = ["0", "-10*t"]\n\n[[loads.pressure]]\nparts = "patch"\np = 1')},
     ["c.toml"]),
    ("output.fields = [\"slip\"] (a friction field) on a frictionless case",
     {"c.toml": case('probes = [[1.0, 0.0]]', 'probes = [[1.0, 0.0]]\nfields = ["slip"]')}, ["c.toml"]),
    # --- issue 48: obstacles and contact pairs
    ("plane obstacle started on the contact face with its normal pointing away (every node at gap 0)",
     reported("plane_normal_away_touching.toml"), ["plane_normal_away_touching.toml"]),
    ("a frictional pair's slave part moved along itself by a [[boundary.displacement]]",
     reported("slave_moved_with_friction.toml"), ["slave_moved_with_friction.toml"]),
    ("sliding = \"small\" slid 2.5 master facets", reported("small_sliding_far.toml"),
     ["run", "small_sliding_far.toml", "--no-vtu", "-o", "out"], {"warning": True}),
    # --- issue 49: a contact pair whose slave side is all prescribed would constrain nothing
    ("a contact pair whose slave part is clamped",
     {"c.toml": (pathlib.Path(__file__).resolve().parent.parent / "cases" / "contact-patch-2d.toml").read_text()
      .replace("[boundary]\n", "[boundary]\nclamped = [\"upper.bottom\"]\n", 1)}, ["c.toml"]),
    # --- issue 50: Archard wear
    ("wear coefficient below 0", {}, ["wear-2d", "--set", "contact.wear_coefficient=-1"]),
    ("wear coefficient without wear = \"archard\"", {}, ["shear-2d", "--set", "contact.wear_coefficient=1e-4"]),
    ("wear on a 1D bar", {}, ["paper-1d", "--set", "contact.wear=\"archard\"", "--set", "contact.wear_coefficient=1"]),
    ("wear with the contact solver penalty-duality", {}, ["wear-2d", "--contact-solver", "penalty-duality"]),
    ("a step whose wear increment passes wear_cap (fixed steps, no halving)", {},
     ["run", "wear-2d", "--no-vtu", "-o", "out", "--set", "contact.wear_coefficient=8e-3"]),
    ("a worn depth past wear_warning of the element size", {},
     ["run", "wear-2d", "--no-vtu", "-q", "-o", "out", "--set", "contact.wear_warning=0.001"], {"warning": True}),
    # --- issue 50: Frémond adhesion
    ("a bond across an open initial gap", {}, ["peel-2d", "--set", "contact.gap=\"0.001*x\""]),
    ("an initial bonding outside [0, 1]", {}, ["peel-2d", "--set", "contact.bonding=1.5"]),
    ("a bond length of 0", {}, ["peel-2d", "--set", "contact.bond_length=0"]),
    ("a bond stiffness without adhesion = \"fremond\"", {}, ["paper-2d", "--set", "contact.bond_stiffness=10"]),
    ("adhesion with friction on a normal compliance law", {},
     ["peel-2d", "--set", "contact.friction=\"coulomb\"", "--set", "contact.mu=0.3", "--set",
      "contact.law=\"normal-compliance\"", "--set", "contact.stiffness=1e4"]),
    ("adhesion with the contact solver penalty-duality", {}, ["peel-2d", "--contact-solver", "penalty-duality"]),
    ("held_by_bond where the supports hold the body already", {}, ["peel-2d", "--set", "contact.held_by_bond=true"]),
    ("a body held by its bond alone on the dual solver", {}, ["pull-off-1d", "--contact-solver", "active-set"]),
    ("a body held by nothing (held_by_bond off)", {}, ["pull-off-1d", "--set", "contact.held_by_bond=false"]),
    ("held_by_bond not a boolean", {}, ["pull-off-1d", "--set", "contact.held_by_bond=\"yes\""]),
    ("a tangential bond together with friction", {},
     ["lap-shear-2d", "--set", "contact.friction=\"coulomb\"", "--set", "contact.mu=0.3"]),
    ("a tangential bond on the contact solver penalty-duality", {}, ["lap-shear-2d", "--contact-solver", "penalty-duality"]),
    ("a negative tangential bond stiffness", {}, ["lap-shear-2d", "--set", "contact.bond_shear_stiffness=-1"]),
    ("a tangential bond in 1D", {}, ["adhesion-bar-1d", "--set", "contact.bond_shear_stiffness=10"]),
    ("a body held by its bond alone pulled off", {}, ["run", "pull-off-1d", "-q", "--no-vtu", "-o", "out", "--set", "time.T=1", "--set", "time.steps=20"]),
    # Issue 51's [adapt]: what cannot be adapted yet is refused at the section, and its keys' ranges.
    ("a negative [adapt] coarsening tolerance", {}, ["hertz-3d-adapt", "--set", "adapt.coarsen_tolerance=-1"]),
    ("[adapt] on a 1D mesh", {}, ["paper-1d", "--set", "adapt.every=1"]),
    ("a negative [adapt] max_level", {}, ["hertz-2d-adapt", "--set", "adapt.max_level=-1"]),
    ("a refine fraction of 0", {}, ["hertz-2d-adapt", "--set", "adapt.refine_fraction=0"]),
    ("a NaN indicator weight", {}, ["hertz-2d-adapt", "--set", "adapt.stress_weight=nan"]),
    ("every indicator weight 0", {}, ["hertz-2d-adapt", "--set", "adapt.stress_weight=0", "--set", "adapt.contact_weight=0", "--set", "adapt.damage_weight=0"]),
    ("a misspelt [adapt] key", {}, ["hertz-2d-adapt", "--set", "adapt.evry=2"]),
]


TIMEOUT = int(os.environ.get("BAD_INPUTS_TIMEOUT", "300"))  # seconds per input
TABLE_HEADER = "| # | bad input | command (in the input's folder) | exit | message |"


def doc_table(text):
    """The lines of the table in docs/reliability.md: from its header to the first line that is not a row."""
    lines = text.splitlines()
    start = lines.index(TABLE_HEADER)
    end = start
    while end < len(lines) and lines[end].startswith("|"):
        end += 1
    return start, end, lines


def main():
    argv = sys.argv[1:]
    if not argv or argv[0].startswith("-"):
        sys.exit("usage: bad_inputs.py VPCONTACT [--doc docs/reliability.md [--update]]")
    vpcontact = os.path.abspath(argv[0])
    doc = pathlib.Path(argv[argv.index("--doc") + 1]) if "--doc" in argv else None
    update = "--update" in argv
    rows, failures = [], []
    # AddressSanitizer's shadow memory exceeds any address-space limit: skip those inputs.
    asan = b"__asan_init" in pathlib.Path(vpcontact).read_bytes()
    for i, (what, files, args, *options) in enumerate(INPUTS, 1):
        options = options[0] if options else {}
        address_space = options.get("address_space")
        warning = options.get("warning", False)
        valid = options.get("valid", False)  # a valid input once refused: it must run (exit 0)
        first = options.get("first")  # a command that must succeed before (a run to resume)
        elide = options.get("elide", [])  # (regex, text): a part of the message that depends on the machine
        if address_space and asan:
            continue
        with tempfile.TemporaryDirectory() as top:
            # Two levels down, so that a path that climbs out (../../escaped) still lands in `top`.
            tmp = pathlib.Path(top) / "in" / "put"
            tmp.mkdir(parents=True)
            for name, content in files.items():
                path = tmp / name
                path.parent.mkdir(parents=True, exist_ok=True)
                if content is None:  # a FIFO that nothing writes: reading it would block forever
                    os.mkfifo(path)
                else:
                    path.write_bytes(content if isinstance(content, bytes) else content.encode())
            if args[0] not in ("run", "cases", "plot", "rnu"):
                args = ["check", *args]
            quiet = ["-q"] if args[0] in ("run", "check") else []
            if first:
                before = subprocess.run([vpcontact, *first, "-q"], cwd=tmp, capture_output=True, text=True,
                                        errors="replace", timeout=TIMEOUT)
                if before.returncode != 0:
                    failures.append(f"{what}: the command before it failed: {before.stderr.strip()[:2000]}")
            try:
                p = subprocess.run([vpcontact, *args, *quiet], cwd=tmp, capture_output=True, text=True,
                                   errors="replace", timeout=TIMEOUT,
                                   preexec_fn=(lambda: resource.setrlimit(resource.RLIMIT_AS, (address_space,) * 2))
                                   if address_space else None)
            except subprocess.TimeoutExpired:
                failures.append(f"{what}: no answer within {TIMEOUT} s (a hang)")
                continue
            if (pathlib.Path(tmp) / "INJECTED").exists():
                failures.append(f"{what}: a shell ran a command in a file name (INJECTED exists)")
            if (pathlib.Path(tmp) / "INJECTED_BY_GEO").exists():
                failures.append(f"{what}: a .geo ran a shell command (INJECTED_BY_GEO exists)")
            if any(pathlib.Path(top).rglob("escaped*")):
                failures.append(f"{what}: a run wrote outside its output folder (escaped exists)")
        message = (p.stderr.strip() or p.stdout.strip()).splitlines()
        message = message[0] if message else ""
        for pattern, text in elide:
            message = re.sub(pattern, text, message)
        sanitizer = "Sanitizer" in p.stderr or "runtime error" in p.stderr
        refused = 1 <= p.returncode <= 127
        warned = p.returncode == 0 and "warning" in p.stderr
        ok = p.returncode == 0 if valid else warned if warning else refused
        if valid:
            message = message or "(runs)"
        if not ok or sanitizer or not message:
            failures.append(f"{what}: exit {p.returncode}: {p.stderr.strip()[:2000]}")
        inp = "`" + " ".join(args).replace("|", "\\|") + "`"
        rows.append(f"| {i} | {what} | {inp} | {p.returncode} | `{message.replace('|', '¦')}` |")
    table = [TABLE_HEADER, "|---|---|---|---|---|", *rows]
    print("\n".join(table))
    if doc and not asan:  # a sanitizer build skips the address-space inputs: its table is shorter
        start, end, lines = doc_table(doc.read_text())
        if lines[start:end] != table:
            if update:
                doc.write_text("\n".join(lines[:start] + table + lines[end:]) + "\n")
            else:
                import difflib
                diff = difflib.unified_diff(lines[start:end], table, str(doc), "vpcontact's messages now", lineterm="")
                failures.append(f"the table in {doc} is stale; regenerate it with "
                                f"scripts/bad_inputs.py {argv[0]} --doc {doc} --update:\n" + "\n".join(diff))
    if failures:
        sys.exit("bad_inputs.py: not a clean error:\n" + "\n".join(failures))


if __name__ == "__main__":
    main()
