"""No public function, class or method of radscene takes a parameter named like a private one."""

from __future__ import annotations

import importlib
import inspect
import pkgutil

import radscene


def _modules():
    for info in pkgutil.walk_packages(radscene.__path__, "radscene."):
        if info.name.endswith("__main__"):  # running it is the command line
            continue
        try:
            yield importlib.import_module(info.name)
        except ImportError:  # an optional extra that is not installed
            continue


def _callables(obj, name):
    """``obj`` and, for a class, its public methods, as (name, callable)."""
    yield name, obj
    if inspect.isclass(obj):
        for attr, value in vars(obj).items():
            if attr.startswith("_"):
                continue
            if isinstance(value, (classmethod, staticmethod)):
                value = value.__func__
            if inspect.isfunction(value):
                yield f"{name}.{attr}", value


def test_no_public_callable_has_a_private_parameter():
    bad = []
    for module in [radscene, *_modules()]:
        for public in getattr(module, "__all__", ()):
            obj = getattr(module, public, None)
            if not callable(obj):
                continue
            for name, item in _callables(obj, public):
                try:
                    params = inspect.signature(item).parameters
                except (TypeError, ValueError):  # builtins and C extensions
                    continue
                bad += [f"{module.__name__}.{name}({p})" for p in params
                        if p.startswith("_")]
    assert not bad, "public callables with private parameters: " + ", ".join(sorted(set(bad)))
