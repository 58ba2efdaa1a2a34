#!/usr/bin/env python3
"""The whole suite's time, as scripts/suite_times.sh measures it:

    python3 scripts/suite_times_table.py count LOG    # from one run's output
    python3 scripts/suite_times_table.py table FILE   # before and after
    python3 scripts/suite_times_table.py tiers FILE   # the last warm run's tiers

`count` prints the JSON fields of one `scripts/test.sh` run: the test
binaries cargo ran (its `Running` lines) and the tests they passed, failed
and ignored (summed over `test result:` lines), in all and per tier (the
script's `the TIER tier` lines, with each tier's seconds). `table` prints,
per commit and target directory, the wall time, the exit status, those
counts and the load the run saw; `tiers`, the last warm run's tiers.
"""

import json
import re
import sys

import results_table


def count(log):
    total = {"binaries": 0, "passed": 0, "failed": 0, "ignored": 0}
    tiers, tier = {}, None
    with open(log, errors="replace") as f:
        for line in f:
            started = re.match(r"scripts/test\.sh: the (\w+) tier: ", line)
            if started:
                tier = tiers.setdefault(started.group(1), {"binaries": 0, "passed": 0, "seconds": None})
            passed_in = re.match(r"scripts/test\.sh: the (\w+) tier passed in (\d+) s", line)
            if passed_in and tier is not None:
                tier["seconds"] = int(passed_in.group(2))
            if re.match(r"\s+Running ", line):
                total["binaries"] += 1
                if tier is not None:
                    tier["binaries"] += 1
            m = re.search(r"test result: \w+\. (\d+) passed; (\d+) failed; (\d+) ignored", line)
            if m:
                for key, value in zip(("passed", "failed", "ignored"), m.groups()):
                    total[key] += int(value)
                if tier is not None:
                    tier["passed"] += int(m.group(1))
    fields = ", ".join(f'"{k}": {v}' for k, v in total.items())
    print(f'{fields}, "tiers": {json.dumps(tiers)}')


def minutes(seconds):
    return f"{seconds // 60} min {seconds % 60:02d} s"


def table(path):
    doc = results_table.load(path)
    print(f"{doc['machine']}; {doc['adapter']}.")
    print()
    print("| commit | target directory | `scripts/test.sh` | exit | test binaries | tests passed | failed | load |")
    print("| --- | --- | --: | --: | --: | --: | --: | --- |")
    for r in doc["runs"]:
        print(f"| {r['commit']} | {r['target']} | {minutes(r['seconds'])} | {r['exit']} | "
              f"{r['binaries']} | {r['passed']} | {r['failed']} | {r['load']} |")


def tiers(path):
    doc = results_table.load(path)
    run = [r for r in doc["runs"] if r["target"] == "warm"][-1]
    print(f"Commit {run['commit']}, warm target directory; {doc['machine']}; load {run['load']}.")
    print()
    print("| tier | test binaries | tests passed | time |")
    print("| --- | --: | --: | --: |")
    for name, t in run["tiers"].items():
        print(f"| {name} | {t['binaries']} | {t['passed']} | {t['seconds']} s |")
    print(f"| `scripts/test.sh` (all three) | {run['binaries']} | {run['passed']} | {minutes(run['seconds'])} |")


def main():
    modes = {"count": count, "table": table, "tiers": tiers}
    if len(sys.argv) != 3 or sys.argv[1] not in modes:
        sys.exit(__doc__)
    modes[sys.argv[1]](sys.argv[2])


if __name__ == "__main__":
    main()
