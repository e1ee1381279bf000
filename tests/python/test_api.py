"""Every public name of the module, and every public attribute and method of its classes, has a
docstring (help(sparsempm) documents the whole API)."""
import inspect

import sparsempm as smpm


def undocumented():
    missing = []
    for name in dir(smpm):
        if name.startswith("_"):
            continue
        obj = getattr(smpm, name)
        if inspect.ismodule(obj):
            continue
        if not (getattr(obj, "__doc__", None) or "").strip():
            missing.append(name)
        if inspect.isclass(obj):
            for member, value in vars(obj).items():
                if member.startswith("_"):
                    continue
                if not (getattr(value, "__doc__", None) or "").strip():
                    missing.append(f"{name}.{member}")
    return missing


def test_every_public_name_has_a_docstring():
    assert undocumented() == []


def test_the_check_sees_a_missing_docstring():
    class Bare:
        def method(self):
            pass

    smpm.Bare = Bare
    try:
        assert undocumented() == ["Bare", "Bare.method"]
    finally:
        del smpm.Bare
