#!/usr/bin/python3
"""Writes the seed inputs of the fuzz targets into OUT/<target>/ (docs/reliability.md).

  case_file   cases/*.toml; the valid case of tests/unit/io/test_case_file.cpp and
              every variant of its table of bad case files; a few cases that use
              the mesh file m.msh and "#set" override lines
  expression  every formula of those case files, for each kind of variables
  gmsh_msh    tests/data/meshes/*.msh; the .msh texts of tests/unit/mesh/
              test_gmsh_reader.cpp; the tests' .geo files meshed by the gmsh
              program in MSH 2.2 and 4.1, ASCII and binary (only our own .geo)

Usage: fuzz/make-seeds.py OUT
"""
import hashlib
import pathlib
import re
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parent.parent


def cxx_literals(text):
    """(position, value) of the C++ string literals in text; raw strings included."""
    out = []
    i = 0
    while i < len(text):
        if text.startswith('R"(', i):
            end = text.index(')"', i + 3)
            out.append((i, text[i + 3:end]))
            i = end + 2
        elif text[i] == '"':
            j = i + 1
            s = []
            while text[j] != '"':
                if text[j] == '\\':
                    s.append({'n': '\n', 't': '\t', '"': '"', '\\': '\\'}.get(text[j + 1], text[j + 1]))
                    j += 2
                else:
                    s.append(text[j])
                    j += 1
            out.append((i, ''.join(s)))
            i = j + 1
        elif text.startswith('//', i):
            i = text.index('\n', i)
        else:
            i += 1
    return out


def bad_case_table(src):
    """kValid and the (from, to) pairs of the BadCase table."""
    valid = re.search(r'const char\* kValid = R"\((.*?)\)";', src, re.S).group(1)
    start = src.index('const std::vector<BadCase> table = {')
    region = src[start:src.index('};', start)]
    entries = []
    for m in re.finditer(r'\{\s*(".*?")\s*\}\s*,', region[region.index('{') + 1:], re.S):
        body = m.group(1)
        # adjacent literals concatenate; entries are separated by commas outside literals
        parts, cur, lits = [], [], cxx_literals(body)
        last_end = 0
        for pos, val in lits:
            between = body[last_end:pos]
            if ',' in between and cur:
                parts.append(''.join(cur))
                cur = []
            cur.append(val)
            # skip to the literal's end
            last_end = body.index('"', pos + 1)
            while body[last_end - 1] == '\\':
                last_end = body.index('"', last_end + 1)
            last_end += 1
        parts.append(''.join(cur))
        if len(parts) >= 2:
            entries.append((parts[0], parts[1]))
    return valid, entries


def write(folder, data):
    folder.mkdir(parents=True, exist_ok=True)
    if isinstance(data, str):
        data = data.encode()
    (folder / hashlib.sha1(data).hexdigest()).write_bytes(data)


def main():
    out = pathlib.Path(sys.argv[1])
    cases = out / 'case_file'
    formulas = set()

    texts = [p.read_text() for p in sorted((ROOT / 'cases').glob('*.toml'))]
    valid, table = bad_case_table((ROOT / 'tests/unit/io/test_case_file.cpp').read_text())
    texts.append(valid)
    for a, b in table:
        if a in valid:
            texts.append(valid.replace(a, b, 1))
    texts.append(valid.replace('generator = "rectangle"\nlower = [0.0, 0.0]\nupper = [2.0, 1.0]\ncells = [10, 5]',
                               'file = "m.msh"').replace('contact = ["patch"]', 'contact = ["contact"]')
                 .replace('where = "abs(y) < 1e-9 && x > 0.6 && x < 1.4"', 'where = "abs(y) < 1e-9 && x > 0.4"'))
    texts.append('#set damage.kappa=0.25\n#set time.steps=3\n#set output.fields=["damage"]\n' + valid)
    texts.append('#set elasticity.kind=plane-stress\n#set case.name="renamed"\n' + valid)
    for t in texts:
        write(cases, t)
        formulas.update(re.findall(r'(?:where|beta0|phi|gap|f0|f2)\s*=\s*(".*?"|\[.*?\])', t))

    exprs = set()
    for f in formulas:
        for s in re.findall(r'"(.*?)"', f) or [f]:
            exprs.add(s)
    exprs.update(['sin(pi*x/2) + t^2 + (y > 0.5 ? 1 : 0)', '-eps_eq + tr_sigma + tr_eps + beta',
                  'min(x, y, z) + max(1, 2) + sum(1, 2, 3) + avg(x, y)', 'x +* 2', '2*w', '1/0', 'sqrt(-1)',
                  'x > 0 && y < 1 || z == 0', 'rint(x) + sign(y) + abs(z) + log2(8) + log10(100) + ln(e) + exp(1)',
                  '-0.01*vm*beta', 'vm > 1 ? -1 : (beta < 0.5 ? 0 : 1)'])
    for e in sorted(exprs):
        for kind in range(3):
            write(out / 'expression', bytes([kind]) + e.encode())

    meshes = out / 'gmsh_msh'
    for p in sorted((ROOT / 'tests/data/meshes').glob('*.msh')):
        write(meshes, p.read_bytes())
    for pos, s in cxx_literals((ROOT / 'tests/unit/mesh/test_gmsh_reader.cpp').read_text()):
        if s.startswith('$MeshFormat'):
            write(meshes, s)
    with tempfile.TemporaryDirectory() as tmp:
        for geo in ['rod.geo', 'square.geo', 'cube.geo']:
            dim = {'rod.geo': 1, 'square.geo': 2, 'cube.geo': 3}[geo]
            for fmt in ['msh22', 'msh41']:
                for binary in [False, True]:
                    msh = pathlib.Path(tmp) / 'out.msh'
                    cmd = ['gmsh', '-v', '0', f'-{dim}', str(ROOT / 'tests/data/meshes' / geo), '-format', fmt,
                           '-o', str(msh), '-clmax', '0.5']
                    if binary:
                        cmd.append('-bin')
                    if fmt == 'msh41':
                        cmd.append('-save_all')
                    subprocess.run(cmd, check=True)
                    write(meshes, msh.read_bytes())
    for d in sorted(out.iterdir()):
        print(f'{d.name}: {len(list(d.iterdir()))} seeds')


if __name__ == '__main__':
    main()
