"""The layout docs/design.md describes: one-way imports, no private names across modules, one public API."""

import ast
from pathlib import Path

import sesp

SRC = Path(sesp.__file__).resolve().parent


def _module_name(path: Path) -> str:
    parts = path.relative_to(SRC.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _imports(path: Path):
    """(module imported, names imported) for every relative import in the file at ``path``."""
    package = _module_name(path) if path.name == "__init__.py" else _module_name(path).rpartition(".")[0]
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom) and node.level:
            base = package.split(".")
            base = base[: len(base) - node.level + 1]
            target = ".".join(base + ([node.module] if node.module else []))
            yield target, [alias.name for alias in node.names]


def _graph():
    graph = {}
    for path in SRC.rglob("*.py"):
        name = _module_name(path)
        graph[name] = set()
        for target, names in _imports(path):
            if target == "sesp" or target == "sesp.kernels":  # `from . import x`: the submodules named
                graph[name] |= {f"{target}.{n}" for n in names}
            else:
                graph[name].add(target)
    return graph


def test_no_module_imports_a_private_name_of_another():
    private = [(p.name, t, n) for p in SRC.rglob("*.py") for t, names in _imports(p) for n in names
               if n.startswith("_") and not n.startswith("__")]  # fmt: skip
    assert private == []


def test_imports_flow_one_way():
    graph = _graph()
    state = {}

    def visit(node, stack):
        state[node] = "open"
        for nxt in graph.get(node, ()):
            if nxt not in graph or nxt == node or nxt == "sesp":
                continue
            assert state.get(nxt) != "open", f"import cycle: {' -> '.join([*stack, nxt])}"
            if nxt not in state:
                visit(nxt, [*stack, nxt])
        state[node] = "done"

    for module in graph:
        if module not in state:
            visit(module, [module])


def test_public_api_lists_what_it_exports():
    for name in sesp.__all__:
        assert hasattr(sesp, name), name
    # modules reached as attributes are not shadowed by functions of the same name
    assert sesp.plot.__name__ == "sesp.plot" and sesp.topology.__name__ == "sesp.topology"
    assert callable(sesp.scan) and callable(sesp.regions.summarize) and callable(sesp.analyze)
