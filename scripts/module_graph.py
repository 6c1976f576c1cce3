#!/usr/bin/env python3
"""The module graph of src/: module A depends on B when a file of src/A/ includes
"B/...". Prints the graph and exits 1 if two modules depend on each other
(directly or through others): each folder is a layer (STYLE.md)."""
import pathlib
import re
import sys

src = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else pathlib.Path(__file__).parent.parent / "src")
include = re.compile(r'^\s*#\s*include\s+"([^"/]+)/[^"]+"', re.M)
graph = {}
for f in sorted(src.rglob("*")):
    if f.suffix not in (".cpp", ".hpp") or f.parent == src:
        continue
    module = f.relative_to(src).parts[0]
    deps = graph.setdefault(module, {})
    for m in include.findall(f.read_text(errors="replace")):
        if m != module and (src / m).is_dir():
            deps.setdefault(m, f.relative_to(src).as_posix())


def reaches(a, b, seen=None):
    seen = seen if seen is not None else set()
    for d in graph.get(a, {}):
        if d == b or (d not in seen and not seen.add(d) and reaches(d, b, seen)):
            return True
    return False


for m in sorted(graph):
    print(f"{m:13} -> {', '.join(sorted(graph[m])) or '(none)'}")
cycles = [(a, b) for a in sorted(graph) for b in sorted(graph[a]) if reaches(b, a)]
for a, b in cycles:
    print(f"cycle: {a} -> {b} (in {graph[a][b]}) and {b} reaches {a} back", file=sys.stderr)
sys.exit(1 if cycles else 0)
