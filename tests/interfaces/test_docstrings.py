"""Every public function and class documents its parameters (numpydoc sections).

Modelled on python-control's docstring test: for each public name of the package's public
modules, the parameters of the function (or the class's constructor) must each appear in the
docstring's ``Parameters``, ``Other Parameters`` or (for result classes) ``Attributes`` section,
as parsed by numpydoc. Methods are not checked: their arguments (x, t) are the same everywhere and
documented once in the API page.
"""

import inspect

import pytest
from numpydoc.docscrape import ClassDoc, FunctionDoc

import gridlbc
from gridlbc import costs, reference, systems, trajectory

MODULES = (gridlbc, systems, costs, reference, trajectory)


def public_objects():
    for module in MODULES:
        names = getattr(module, "__all__", None)
        if names is None:
            names = [
                n
                for n in dir(module)
                if not n.startswith("_")
                and getattr(getattr(module, n), "__module__", "").startswith(module.__name__)
            ]
        for name in names:
            obj = getattr(module, name)
            if inspect.ismodule(obj) or not callable(obj):
                continue
            if inspect.isclass(obj) and issubclass(obj, Exception):  # warnings and errors
                continue
            yield f"{module.__name__}.{name}", obj


def documented_names(obj) -> set[str]:
    doc = ClassDoc(obj) if inspect.isclass(obj) else FunctionDoc(obj)
    sections = doc["Parameters"] + doc["Other Parameters"]
    if inspect.isclass(obj):
        sections = sections + doc["Attributes"]
    return {n.strip().lstrip("*") for entry in sections for n in entry.name.split(",")}


@pytest.mark.parametrize(("name", "obj"), [pytest.param(n, o, id=n) for n, o in public_objects()])
def test_parameters_documented(name, obj):
    parameters = [
        p
        for p in inspect.signature(obj).parameters
        if p not in ("self", "cls") and not p.startswith("_")
    ]
    missing = [p for p in parameters if p not in documented_names(obj)]
    assert not missing, f"{name} does not document {missing} (numpydoc Parameters section)"
