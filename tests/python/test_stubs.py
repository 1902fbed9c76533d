"""tests/python/test_stubs.py — python/aquarelle/_aquarelle.pyi matches the module: the same public
names, classes with the same public members, functions and methods with the same parameters."""
import ast
import inspect
import os
import re

import aquarelle._aquarelle as native

STUB = os.path.join(os.path.dirname(native.__file__), "_aquarelle.pyi")


def stub_tree():
    with open(STUB) as f:
        return ast.parse(f.read())


def stub_params(fn):
    a = fn.args
    names = [x.arg for x in a.posonlyargs + a.args + a.kwonlyargs]
    return [n for n in names if n != "self"]


def native_params(obj):
    """Parameter names from pybind11's signature line(s): `name(arg: type = default, *, kw: ...) -> ret`."""
    doc = (obj.__doc__ or "").strip().splitlines()[0]
    inner = doc[doc.index("(") + 1: doc.rindex(")")]
    depth, cur, parts = 0, "", []
    for ch in inner:
        if ch in "[(" : depth += 1
        if ch in "])" : depth -= 1
        if ch == "," and depth == 0:
            parts.append(cur); cur = ""
        else:
            cur += ch
    if cur.strip(): parts.append(cur)
    names = [re.split(r"[:=]", p.strip())[0].strip() for p in parts]
    return [n for n in names if n not in ("self", "*", "")]


def public(names):
    return {n for n in names if not n.startswith("_") or n in ("__getitem__", "__contains__", "__len__")}


def test_the_stub_lists_every_public_name_and_no_other():
    tree = stub_tree()
    stubbed = {n.name for n in tree.body if isinstance(n, (ast.FunctionDef, ast.ClassDef))}
    module = {n for n in dir(native) if not n.startswith("_")}
    assert stubbed == module


def test_functions_and_methods_have_the_stubs_parameters():
    tree = stub_tree()
    for node in tree.body:
        if isinstance(node, ast.FunctionDef):
            assert stub_params(node) == native_params(getattr(native, node.name)), node.name
        elif isinstance(node, ast.ClassDef) and node.name != "Error":
            cls = getattr(native, node.name)
            members = {n.name: n for n in node.body if isinstance(n, ast.FunctionDef)}
            have = public(n for n in dir(cls) if not (n.startswith("__") and n not in ("__getitem__", "__contains__", "__len__")))
            assert public(members) == have, node.name
            for name, fn in members.items():
                is_property = any(isinstance(d, ast.Name) and d.id == "property" for d in fn.decorator_list)
                attr = inspect.getattr_static(cls, name)
                if is_property:
                    assert isinstance(attr, property), (node.name, name)
                else:
                    assert stub_params(fn) == native_params(getattr(cls, name)), (node.name, name)
