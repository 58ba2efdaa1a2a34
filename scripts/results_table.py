"""Shared by the table scripts of docs/: a kept result file (the JSON the
measuring scripts write with scripts/results_json.sh) and the line under
a table's heading that says where its figures come from."""

import json


def load(path):
    """The result file at `path`."""
    with open(path) as f:
        return json.load(f)


def grouped(runs, key, value=lambda run: run):
    """`value` of each of `runs`, in lists by `run[key]`, in the order the
    keys first come."""
    groups = {}
    for run in runs:
        groups.setdefault(run[key], []).append(value(run))
    return groups


def provenance(doc):
    """The commit, adapter, machine and load a result file names."""
    return f"Commit {doc['commit']}; {doc['adapter']}; {doc['machine']}; load {doc['load']}."
