# SPDX-License-Identifier: BSD-3-Clause
"""Reading the tables of `smpm stability`, `smpm transport-stability` and `smpm spectrum` (CSV).

A result has one name in C++, Python and the tables' columns (the screen shows its symbol):

    critical_courant    C* spectral     CriticalCourant.critical_courant (critical_courant())
    simulation_courant  C* simulation   SimulationCourant.simulation_courant
    critical_fourier    F*              CriticalFourier.critical_fourier (critical_fourier())
    rho_T               rho(T)          SpectralRadius.rho_T, CriticalCourant.rho_T, ...
    configuration       configuration   ConfigurationSweep.configuration

    rows = sparsempm.read_table("stability.csv")   # [{column: cell}], cells as text
    rows[0]["critical_courant"]                     # also from a table of the earlier names

The tables of the previous release named some columns differently (EARLIER_COLUMNS); they are
read under the current names in this release only. This file needs only the standard library,
so the scripts of analysis/ and the tests load it by its path where the package does not import.
"""

import csv
import io
import os

__all__ = ["EARLIER_COLUMNS", "read_table", "current_columns"]

# The earlier name of a column -> its name now (read in this release only).
EARLIER_COLUMNS = {
    "c_spectral": "critical_courant",      # smpm stability, C*(spec)
    "config_spectral": "configuration",    # smpm stability and transport-stability
    "c_simulation": "simulation_courant",  # smpm stability, C*(sim)
    "f_spectral": "critical_fourier",      # smpm transport-stability, F*
}


def current_columns(columns):
    """The column names with every earlier name replaced by its current one."""
    return [EARLIER_COLUMNS.get(c, c) for c in columns]


def read_table(table):
    """The rows of a table (a path, or its text as a list of lines or a file object) as dicts
    keyed by the current column names, whether the file has the current or the earlier ones;
    the cells as the file holds them (text: "" where not computed, "none" where no value held)."""
    if isinstance(table, (str, os.PathLike)):
        with open(table, newline="") as f:
            return read_table(io.StringIO(f.read()))
    reader = csv.reader(table)
    header = next(reader, None)
    if header is None:
        return []
    columns = current_columns(header)
    return [dict(zip(columns, row)) for row in reader]
