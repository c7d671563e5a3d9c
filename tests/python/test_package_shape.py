# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""The shape of the Python package (issue 29, "Python with a face"), read from the source:

- no import cycle between the modules of cgms;
- no module over 600 lines;
- no module outside ``cgms/cli/`` imports the command line;
- every name of ``cgms.__all__`` resolves, and ``import cgms`` starts neither LAMMPS nor
  matplotlib.

The import graph has an edge for every ``import``/``from ... import`` of a cgms module,
at the top of a file or inside a function (a cycle through a lazy import is still two
modules that need each other), to the module and to each package it is in. Only the
block under ``if __name__ == "__main__":`` is left out: it runs when the file is the
program (``python3 -m cgms.tissue``), never when the module is imported.
"""

import ast
import os
import subprocess
import sys

import pytest

from cgmstest import ROOT

PACKAGE = ROOT / "python" / "cgms"
MAX_LINES = 600


def modules(package=PACKAGE):
    """{module name: path} of every file of the package in folder ``package``."""
    found = {}
    for path in sorted(package.rglob("*.py")):
        parts = list(path.relative_to(package.parent).with_suffix("").parts)
        found[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = path
    return found


def is_main_block(node):
    """Whether ``node`` is ``if __name__ == "__main__":``."""
    test = getattr(node, "test", None)
    return (isinstance(node, ast.If) and isinstance(test, ast.Compare)
            and isinstance(test.left, ast.Name) and test.left.id == "__name__"
            and any(isinstance(c, ast.Constant) and c.value == "__main__"
                    for c in test.comparators))


def imports(tree):
    """The import nodes of a module, those under a ``__main__`` guard left out."""
    found, todo = [], [tree]
    while todo:
        node = todo.pop()
        for child in ast.iter_child_nodes(node):
            if is_main_block(child):
                continue
            if isinstance(child, (ast.Import, ast.ImportFrom)):
                found.append(child)
            todo.append(child)
    return found


def imported(name, path, known):
    """The cgms modules module ``name`` (file ``path``) imports, with their packages."""
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    targets = set()
    for node in imports(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            targets |= {a.name for a in node.names}
            continue
        if node.level:
            base = package.split(".")
            base = base[:len(base) - node.level + 1]
            source = ".".join(base + ([node.module] if node.module else []))
        else:
            source = node.module or ""
        for a in node.names:   # 'from pkg import module' imports the module
            full = f"{source}.{a.name}"
            targets.add(full if full in known else source)
    edges = set()
    for target in targets:
        parts = target.split(".")
        for k in range(1, len(parts) + 1):
            step = ".".join(parts[:k])
            # a package the importer is in is imported already
            if step in known and step != name and not name.startswith(step + "."):
                edges.add(step)
    return edges


def import_graph(files=None):
    files = files or modules()
    return {name: imported(name, path, files) for name, path in files.items()}


def cycles(graph):
    """The strongly connected components of more than one module, or with a self loop
    (Tarjan), each as a sorted list."""
    index, low, stack, on, found = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in graph.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            part = []
            while True:
                w = stack.pop()
                on.discard(w)
                part.append(w)
                if w == v:
                    break
            if len(part) > 1 or v in graph.get(v, ()):
                found.append(sorted(part))

    sys.setrecursionlimit(max(1000, 10 * len(graph)))
    for v in sorted(graph):
        if v not in index:
            visit(v)
    return found


def test_the_graph_sees_the_imports():
    """The graph itself: the command line imports its commands and the library, and a
    module's lazy import counts (so a check below cannot pass on an empty graph)."""
    graph = import_graph()
    assert {"cgms.cli.study", "cgms.cli.dry", "cgms.cli.mfc"} <= graph["cgms.cli"]
    assert "cgms.study" in graph["cgms.cli.study"]
    assert "cgms.mfc.newton" in graph["cgms.mfc.run"]   # imported inside a function
    assert "cgms.mfc" in graph["cgms.shear"]             # the package of cgms.mfc.run


def test_no_import_cycle():
    assert cycles(import_graph()) == []


def test_a_cycle_is_found(tmp_path):
    """The check fails on a cycle: two modules of a copy of the package that import each
    other (one of them lazily, as tissue.py imported cli.py before issue 29)."""
    package = tmp_path / "cgms"
    (package / "cli").mkdir(parents=True)
    (package / "__init__.py").write_text("")
    (package / "tissue.py").write_text("def main():\n    from .cli import tissue\n")
    (package / "cli" / "__init__.py").write_text("")
    (package / "cli" / "tissue.py").write_text("from .. import tissue\n")
    assert cycles(import_graph(modules(package))) == [["cgms.cli.tissue", "cgms.tissue"]]


def test_no_module_over_600_lines():
    long = {name: n for name, path in modules().items()
            if (n := len(path.read_text().splitlines())) > MAX_LINES}
    assert long == {}, f"split these by job: {long}"


def function_lengths(source):
    """(first line, length in lines) of every function body in LAMMPS-formatted C++: a body
    opens with '{' alone in column 0 and closes with '}' in column 0."""
    lines = source.split("\n")
    start = None
    for i, line in enumerate(lines):
        if line.startswith("{"):
            start = i
        elif line.startswith("}") and start is not None:
            yield lines[start - 1].strip(), i - start
            start = None


def test_no_cpp_function_over_150_lines():
    # issue 29: small functions with one job; a long one is split where its steps part
    long = [f"{path.name}: {head[:60]} ({n} lines)"
            for path in sorted((ROOT / "src" / "CGMS").glob("*.cpp"))
            for head, n in function_lengths(path.read_text()) if n > 150]
    assert not long, "\n".join(long)


def test_a_long_function_is_found():
    body = "\n".join(["  x++;"] * 151)
    assert [n for _, n in function_lengths(f"void f()\n{{\n{body}\n}}\n")] == [152]


def test_only_the_command_line_imports_it():
    """cgms.cli is the top: no library module imports it (the CLI's own modules may)."""
    graph = import_graph()
    users = sorted(name for name, edges in graph.items()
                   if not (name == "cgms.cli" or name.startswith("cgms.cli."))
                   and any(e == "cgms.cli" or e.startswith("cgms.cli.") for e in edges))
    assert users == ["cgms.__main__"]   # python3 -m cgms runs the command line


def test_every_public_name_resolves_without_lammps_or_matplotlib():
    """Every name of cgms.__all__ resolves to a function of its module, and neither
    ``import cgms`` nor resolving all of them imports LAMMPS or matplotlib."""
    code = ("import sys, cgms\n"
            "heavy = ('lammps', 'matplotlib', 'numpy')\n"
            "print(sorted(m for m in heavy if m in sys.modules))\n"
            "for name in cgms.__all__:\n"
            "    assert callable(getattr(cgms, name)), name\n"
            "print(sorted(m for m in heavy[:2] if m in sys.modules))\n"
            "print(sorted(set(cgms.__all__) & set(dir(cgms))) == sorted(cgms.__all__))\n")
    env = dict(os.environ, PYTHONPATH=str(PACKAGE.parent))
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          env=env, cwd=ROOT)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.split("\n")[:3] == ["[]", "[]", "True"], proc.stdout


@pytest.mark.parametrize("name", ["cgms.cli", "cgms.mfc", "cgms.drying", "cgms.calibration"])
def test_subpackages(name):
    """The subpackages of the target layout exist, each with its own modules."""
    found = [m for m in modules() if m.startswith(name + ".")]
    assert found, name
