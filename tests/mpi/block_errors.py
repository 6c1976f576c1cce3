#!/usr/bin/env python3
"""A generated mesh built by blocks under mpiexec (issue 30, parallel/block_part.hpp) refuses a wrong
case with the error one process gives on the whole mesh, word for word: the checks that need the
whole mesh are made by all ranks together (validate_blocks). Each wrong input is run on one process
and on --ranks ranks; the error lines must be the same.

  block_errors.py --vpcontact BIN --mpiexec MPIEXEC --work DIR --ranks P -- CASE_FILE

CASE_FILE: a valid case with a generated box (tests/mpi/cases/blocks-3d.toml), or with a Gmsh mesh
refined on every rank (tests/mpi/cases/refine-3d.toml, whose wrong inputs are its own). Prints "block
errors: PASSED" or what differs and "block errors: FAILED". Python standard library only.
"""
import os
import re
import subprocess

import case_runs

# Wrong in the ways users get it wrong: --set overrides of the valid case, or (a pair) a line of it
# replaced by another.
WRONG = {
    "a clamped part misspelt": ['boundary.clamped=["tpo"]'],
    "a predicate that selects nothing": ['mesh.part[0].where="z < -1"'],
    "a probe outside the body": ["output.probes=[[0.5, 0.5, 9.0]]"],
    "a material whose where selects no cell": ['material[0].where="x > 5"'],
    "a body not held (only its symmetry plane)": ('clamped = ["top"]', ""),
    "Γ3 clamped": ['boundary.clamped=["zone"]'],
    "Γ3 on a symmetry plane": ['boundary.symmetry=["zone", "front"]'],
}

# A Gmsh mesh refined on every rank (tests/mpi/cases/refine-3d.toml): its parts and regions are the
# file's physical groups.
WRONG_REFINED = {
    "a clamped part misspelt": ['boundary.clamped=["clampd"]'],
    "a predicate that selects nothing": ['mesh.part[0].where="x < -1"'],
    "a probe outside the body": ["output.probes=[[0.5, 0.5, 3.0]]"],
    "a material's region misspelt": ['material[0].regions=["bdy"]'],
    "Γ3 clamped": ['boundary.clamped=["contact"]'],
    "a body not held (only its symmetry plane)": ('clamped = ["clamped"]', ""),
}


def error_line(cmd):
    r = subprocess.run(cmd, capture_output=True, text=True)
    lines = [l for l in (r.stdout + r.stderr).splitlines() if l.startswith("vpcontact: error:")]
    return r.returncode, lines[0] if lines else "(no error line)\n" + r.stdout + r.stderr


def main():
    args = case_runs.parse(case_runs.parser(__doc__.splitlines()[0]))
    problems = []
    os.makedirs(args.work, exist_ok=True)
    wrongs = WRONG_REFINED if os.path.basename(args.case[0]).startswith("refine") else WRONG
    for k, (what, wrong) in enumerate(wrongs.items()):
        out = os.path.join(args.work, f"wrong{k}")
        case, opts = args.case, []
        if isinstance(wrong, tuple):  # the case file with a line replaced, its mesh file's path made absolute
            with open(args.case[0]) as f:
                text = f.read()
            assert wrong[0] in text, wrong[0]
            text = re.sub(r'^file = "([^"]+)"', lambda m: 'file = "%s"' % os.path.join(
                os.path.dirname(os.path.abspath(args.case[0])), m.group(1)), text, flags=re.M)
            edited = os.path.join(args.work, f"wrong{k}.toml")
            with open(edited, "w") as f:
                f.write(text.replace(wrong[0], wrong[1]))
            case = [edited, *args.case[1:]]
        else:
            opts = [a for s in wrong for a in ("--set", s)]
        one = [args.vpcontact, "run", *case, *opts, "-o", out + ".1", "-q", "--no-vtu"]
        many = [args.mpiexec, "-n", str(args.ranks), args.vpcontact, "run", *case, *opts, "-o", out + ".p",
                "-q", "--no-vtu"]
        rc1, e1 = error_line(one)
        rcp, ep = error_line(many)
        print(f"{what}:\n  1 process: {e1}\n  {args.ranks} ranks:   {ep}")
        if rc1 == 0 or rcp == 0:
            problems.append(f"{what}: not refused (exit {rc1} on one process, {rcp} on {args.ranks} ranks)")
        elif e1 != ep:
            problems.append(f"{what}: the errors differ")
    case_runs.report("block errors", problems)


if __name__ == "__main__":
    main()
