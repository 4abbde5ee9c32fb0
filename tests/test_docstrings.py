"""Every public function and class of liquidamp has a docstring (numpydoc)."""

import importlib
import inspect
import pkgutil

import liquidamp


def _public_objects():
    for info in pkgutil.walk_packages(liquidamp.__path__, "liquidamp."):
        module = importlib.import_module(info.name)
        if info.name.split(".")[-1].startswith("_"):
            continue
        names = getattr(module, "__all__", None)
        if names is None:
            names = [n for n, o in vars(module).items()
                     if not n.startswith("_") and (inspect.isfunction(o) or inspect.isclass(o))
                     and getattr(o, "__module__", None) == module.__name__]
        for name in names:
            obj = getattr(module, name)
            if inspect.isfunction(obj) or inspect.isclass(obj):
                yield f"{info.name}.{name}", obj


def test_every_public_object_is_documented():
    missing = [name for name, obj in _public_objects() if not (obj.__doc__ or "").strip()]
    assert not missing, f"public objects without a docstring: {missing}"


def test_there_are_many_public_objects():
    assert len(list(_public_objects())) > 100
