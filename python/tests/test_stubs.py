"""The type stubs (``tessera/_tessera.pyi``) name the native module's parameters with the
defaults it really has, and leave out nothing it exports."""

import ast
import inspect
from pathlib import Path

import pytest

import tessera._tessera as native


def stub_tree():
    path = Path(native.__file__).parent / "_tessera.pyi"
    return ast.parse(path.read_text())


def stub_parameters(node):
    """(name, default as written) of a stub function's parameters, `self` left out."""
    args = node.args
    names = [a.arg for a in args.args]
    defaults = [None] * (len(names) - len(args.defaults)) + [
        ast.literal_eval(d) for d in args.defaults
    ]
    pairs = list(zip(names, defaults))
    return [p for p in pairs if p[0] != "self"]


def runtime_parameters(obj):
    """(name, default) of the native callable's parameters; PyO3 writes a tuple default as
    `...`, which stands for any value."""
    out = []
    for p in inspect.signature(obj).parameters.values():
        if p.name == "self":
            continue
        out.append((p.name, None if p.default is inspect.Parameter.empty else p.default))
    return out


def assert_same(where, stub, runtime):
    assert [n for n, _ in stub] == [n for n, _ in runtime], where
    for (name, want), (_, got) in zip(stub, runtime):
        if got is not Ellipsis:
            assert want == got, f"{where}: {name} defaults to {got!r}, the stub says {want!r}"


def stubbed():
    """Every function and class method the stubs declare, as (qualified name, node)."""
    for node in stub_tree().body:
        if isinstance(node, ast.FunctionDef):
            yield node.name, node
        elif isinstance(node, ast.ClassDef):
            for item in node.body:
                if isinstance(item, ast.FunctionDef):
                    yield f"{node.name}.{item.name}", item


@pytest.mark.parametrize("name,node", list(stubbed()), ids=lambda v: v if isinstance(v, str) else "")
def test_stub_parameters_match_the_module(name, node):
    owner, _, member = name.partition(".")
    obj = getattr(native, owner)
    if member == "__init__":
        target = obj  # PyO3 gives the class the constructor's signature
    elif member:
        target = getattr(obj, member)
        if isinstance(target, property) or not callable(target):
            return  # properties: their names are checked below
    else:
        target = obj
    assert_same(name, stub_parameters(node), runtime_parameters(target))


def test_stubs_cover_every_export():
    declared = set()
    for node in stub_tree().body:
        if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            declared.add(node.name)
            if isinstance(node, ast.ClassDef):
                members = {n.name for n in node.body if isinstance(n, ast.FunctionDef)}
                obj = getattr(native, node.name)
                public = {m for m in dir(obj) if not m.startswith("__")}
                if not issubclass(obj, BaseException):
                    assert public <= members, f"{node.name}: {public - members} not stubbed"
    exported = {n for n in dir(native) if not n.startswith("__")}
    assert exported <= declared, f"not stubbed: {exported - declared}"
