"""What the scripts that run one case several times under mpiexec share (reproducible.py,
within_bodies.py): their command line, --vpcontact BIN --mpiexec MPIEXEC --work DIR --ranks P
[their own options] -- CASE [run options...]. Python standard library only."""
import argparse


def parser(description):
    """The shared options; a script adds its own before calling parse()."""
    p = argparse.ArgumentParser(description=description)
    p.add_argument("--vpcontact", required=True)
    p.add_argument("--mpiexec", required=True)
    p.add_argument("--work", required=True)
    p.add_argument("--ranks", type=int, default=2)
    return p


def parse(p):
    """The arguments, with the case and its run options (after "--") in args.case."""
    p.add_argument("case", nargs=argparse.REMAINDER)
    args = p.parse_args()
    if args.case and args.case[0] == "--":
        args.case = args.case[1:]
    return args
