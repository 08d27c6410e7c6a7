"""Input/output: atomic writers, data loaders (Stribeck CSV, EPOS exports, EMPS .mat, recordings)."""

from ._atomic import atomic_path as atomic_path, save_figure as save_figure, write_csv as write_csv, write_json as write_json
