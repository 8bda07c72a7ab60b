"""Reproduce the paper end to end: Tables 2, 3 and 5, Figures 6 to 10 and 12, and a report.

>>> from ik7r.reproduce import QUICK, reproduce
>>> result = reproduce("out/paper", plan=QUICK)      # doctest: +SKIP
>>> sorted(result.files)                             # doctest: +SKIP
['figure10', 'figure12', 'figure6', ..., 'report', 'table2', 'table3', 'table5']

One module per group: :mod:`.simulation1` (Table 2, Table 3, Figure 8), :mod:`.wrist`
(Figures 6 and 7), :mod:`.workspace` (Table 5, Figure 10), :mod:`.plots` (drawing),
:mod:`.report` (CSV and ``report.md``), :mod:`.published` (the paper's numbers), :mod:`.run`.
Nothing heavy is imported until one of the names below is used.
"""

from __future__ import annotations

__all__ = ["FULL", "QUICK", "Plan", "Reproduction", "plan_units", "reproduce"]


def __getattr__(name: str):
    if name in __all__:
        from . import run

        return getattr(run, name)
    raise AttributeError(f"module 'ik7r.reproduce' has no attribute {name!r}")
