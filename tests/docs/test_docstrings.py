"""The >>> examples in the docstrings of every ik7r module run and print what they say."""

from __future__ import annotations

import doctest
import importlib
import pkgutil

import numpy as np
import pytest

import ik7r


def modules() -> list[str]:
    names = ["ik7r"]
    for info in pkgutil.walk_packages(ik7r.__path__, "ik7r."):
        if info.name.endswith("__main__"):
            continue
        names.append(info.name)
    return sorted(names)


def _examples(name: str) -> list[doctest.DocTest]:
    module = importlib.import_module(name)
    tests = doctest.DocTestFinder(exclude_empty=True).find(module, name)
    return [t for t in tests if t.examples]


def test_some_docstrings_have_examples():
    assert sum(len(_examples(name)) for name in modules()) >= 3


@pytest.mark.parametrize("name", [name for name in modules() if _examples(name)])
def test_docstring_examples(name, tmp_path, monkeypatch):
    tests = _examples(name)
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("MPLBACKEND", "Agg")
    flags = doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE
    runner = doctest.DocTestRunner(optionflags=flags)
    with np.printoptions(legacy="1.25"):  # scalars print as 1.0, not np.float64(1.0)
        for test in tests:
            test.globs.setdefault("np", np)
            runner.run(test)
    result = runner.summarize(verbose=False)
    assert result.failed == 0, f"{result.failed} of {result.attempted} examples failed in {name}"
