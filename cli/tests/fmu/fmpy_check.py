"""Runs daec's FMUs in FMPy, a real importer: validation, simulation, a lost layer.

Usage: fmpy_check.py DP.fmu CHAIN.fmu OUT_DIR. Writes OUT_DIR/dp.csv and OUT_DIR/chain.csv
(time, then every output) and OUT_DIR/report.json, one JSON object with: the validation problems of each
FMU and the log messages of the run whose pin jumps.
"""
import json
import sys

import numpy as np
from fmpy import simulate_fmu
from fmpy.validation import validate_fmu

dp, chain, out = sys.argv[1:4]
report = {"problems": {}, "jump_log": []}
for name, path in (("dp", dp), ("chain", chain)):
    report["problems"][name] = [str(p) for p in validate_fmu(path)]
    result = simulate_fmu(path, stop_time=2.0, output_interval=1 / 60)
    names = result.dtype.names
    rows = np.array([list(r) for r in result])
    np.savetxt(f"{out}/{name}.csv", rows, delimiter=",", header=",".join(names),
               comments="", fmt="%.17g")


def logger(env, instance, status, category, message):
    report["jump_log"].append([status, message.decode()])


# The pinned end jumps 5 cm at t = 0.3 s: the first link is suddenly too long.
signal = np.array([(0.0, 0.0), (0.3, 0.0), (0.3, 0.05), (1.0, 0.05)],
                  dtype=[("time", np.float64), ("pin[0].x", np.float64)])
simulate_fmu(chain, stop_time=1.0, output_interval=1 / 60, input=signal, logger=logger)
with open(f"{out}/report.json", "w") as f:
    json.dump(report, f)
