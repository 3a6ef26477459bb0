"""The mean loads do not depend on the machine's number of cores.

A BLAS product over the Gauss nodes (``values @ weights``) is split between OpenBLAS's
threads, and the last bits of its sum then depend on how many there are: the mean crank-pin
and main-bearing loads of three built-in layouts with gas differed between one thread and
two.  :func:`balance.core._numerics.node_stats` sums with numpy's own loop; here the same
loads are computed in processes with one and with two BLAS threads.
"""

from __future__ import annotations

import os
import subprocess
import sys

import numpy as np

# the outputs as the Dataset holds them (its variables are these catalogue values), read
# without building the Dataset: the process then starts without xarray and pandas
SCRIPT = """
import numpy as np
import balance
from balance.core.catalogue import value

result = balance.compute_result("v8-crossplane-gas", bearings=True)
for name in ("main_bearing_mean_load", "crank_pin_mean_load"):
    print(np.asarray(value(result, name), dtype=np.float64).tobytes().hex())
"""


def _means(threads: int) -> str:
    env = {**os.environ, "OPENBLAS_NUM_THREADS": str(threads), "OMP_NUM_THREADS": str(threads)}
    done = subprocess.run(
        [sys.executable, "-c", SCRIPT], capture_output=True, text=True, env=env, check=True
    )
    return done.stdout.strip()


def test_mean_loads_are_the_same_bits_with_one_and_two_blas_threads():
    """The crossplane V8 with gas: its mean main-bearing loads differed in the last bit
    between one BLAS thread and two before the node sums left BLAS."""
    one, two = _means(1), _means(2)
    assert one == two
    mains = np.frombuffer(bytes.fromhex(one.splitlines()[0]), dtype=np.float64)
    assert np.all(np.isfinite(mains)) and np.all(mains > 0)
