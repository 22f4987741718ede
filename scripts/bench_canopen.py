"""Times python `canopen.import_od` over a list of files: the baseline for benches/corpus.rs.

Prints one line: the best wall-clock time, in seconds, of one pass over all the files, taken
over `--passes` passes (after one warm-up pass).
"""
import argparse
import logging
import time

import canopen

logging.disable(logging.CRITICAL)

parser = argparse.ArgumentParser()
parser.add_argument("--passes", type=int, default=5)
parser.add_argument("files", nargs="+")
args = parser.parse_args()

def one_pass():
    for path in args.files:
        canopen.import_od(path)

one_pass()
best = float("inf")
for _ in range(args.passes):
    start = time.perf_counter()
    one_pass()
    best = min(best, time.perf_counter() - start)
print(f"{best:.6f}")
