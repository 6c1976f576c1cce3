#!/usr/bin/env python3
"""Counts the places in src/ that branch on friction or on contact pairs (issue 49's measure).

Two measures, each over code lines (comments and strings stripped; mortar/ left out):
- broad: a condition (`if (`, `while (`, `? :`) whose line names friction (frictional(), a friction
  law or flag, a contact block > 1, a tangent dof) or pairs (a pair, a slave/master side, a row's
  masters), including the friction and pair modules' own inner logic;
- asks: a condition that asks *whether* there is friction (frictional(), a block > 1, a friction
  law pointer tested, μ > 0) or an `if` that asks whether there are pairs (pairs.empty(), a row's
  pair >= 0, large sliding, a row's masters empty). This is the issue's "is it frictional?"
  (45 in 18 files at 3300fc2 by the issue's count; 41 in 14 by this one) and its pair `if`s (28;
  23 here).
Usage: scripts/contact_branches.py [--list] [SRC_DIR]."""
import re
import sys
from pathlib import Path

CONDITION = re.compile(r"\bif\s*\(|\bwhile\s*\(|\?[^:]*:")
FRICTION = re.compile(r"fricti|block_?\s*>\s*1|\bblock\s*==\s*1|row_friction|\bmu\b\s*>\s*0|tangent_dof", re.I)
ASKS_FRICTION = re.compile(
    r"\bfrictional\b|contact_block\s*[>=]=?\s*1|\bblock\s*>\s*1|\bblock\s*==\s*1|\bb\s*>\s*1|row_friction|"
    r"frictions\.empty\(\)|\bfriction_?\)|\bfriction\s*\?|\(\s*!?friction\s*&&|&&\s*!?friction\b\s*[)&]|"
    r"\.friction\s*\?|\.friction\)|friction\.get\(\)|\bmu\b\s*>\s*0", re.I)
ASKS_PAIRS = re.compile(
    r"pairs\.empty\(\)|has_pairs|\bpair\s*[<>]=?\s*0|\.pair\s*[<>]=?\s*0|large_sliding|masters\.empty\(\)|"
    r"master_mean\.(size|nonZeros)\(\)|\bpairs\s*[?&|)]|\(\s*!?pairs\b|pair_sides_mixed|\bslides\(", re.I)
PAIRS = re.compile(r"\bpairs\b|\.pair\b|\bpair\.|has_pairs|\bpair_|_pair\b|masters|master_mean|slave|large_sliding", re.I)


def code_lines(path):
    in_block = False
    for n, line in enumerate(path.read_text(errors="replace").splitlines(), 1):
        if in_block:
            if "*/" not in line:
                continue
            line, in_block = line.split("*/", 1)[1], False
        line = re.sub(r"/\*.*?\*/", "", line)
        if "/*" in line:
            line, in_block = line.split("/*", 1)[0], True
        line = re.sub(r'"(\\.|[^"\\])*"', '""', line)  # strings (messages) are not branches
        line = line.split("//", 1)[0]
        line = re.sub(r"std::pair\b|\bstd::make_pair\b", "", line)  # a C++ pair is not a contact pair
        yield n, line


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    listing = "--list" in sys.argv
    src = Path(args[0] if args else "src")
    counts = {"friction": [], "pairs": [], "asks whether frictional": [], "asks whether pairs (ifs)": []}
    for path in sorted(src.rglob("*.[ch]pp")):
        if path.parent.name == "mortar":  # the pairing's own geometry: slave and master are its vocabulary
            continue
        for n, line in code_lines(path):
            if not CONDITION.search(line):
                continue
            where = f"{path}:{n}: {line.strip()}"
            if FRICTION.search(line):
                counts["friction"].append(where)
            if PAIRS.search(line):
                counts["pairs"].append(where)
            if ASKS_FRICTION.search(line):
                counts["asks whether frictional"].append(where)
            if re.search(r"\bif\s*\(", line) and ASKS_PAIRS.search(line):
                counts["asks whether pairs (ifs)"].append(where)
    for kind, places in counts.items():
        files = len({p.split(":")[0] for p in places})
        print(f"{kind}: {len(places)} places in {files} files")
        if listing:
            for p in places:
                print("  " + p)


if __name__ == "__main__":
    main()
