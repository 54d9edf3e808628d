"""Parametric sweeps: many analyses of one base model, in parallel, resumable.

The sweep file format is :mod:`pounding_cli.model.sweep`; the columns of a sweep's summary
table, and the JSON Schema of one row, are :mod:`.columns`. Both are documented in
docs/sweep.md.

This package must not load numpy or numba when imported: worker processes import it before
their thread settings take effect.
"""
