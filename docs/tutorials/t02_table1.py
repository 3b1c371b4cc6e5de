"""
Table 1 on a few seeds
======================

Table 1 of the paper compares, on random Gaussian-hill terrains, the coverage CAO reaches from a
CVT start on S' with the coverage from random and corner starts, for teams of 5 to 20 UAVs.
:func:`uavcov.paper.reproduce` runs it into a results folder (``runs.csv``, one ``.npz``
per run, ``table1.md``). The published table uses 40 seeds and 500 iterations
(``uavcov reproduce table1``, about an hour on two cores); here 3 seeds, one team size and 40
iterations, so the numbers are a preview, not the table.
"""

# %%
import tempfile
from pathlib import Path

from uavcov import paper, plotting

out = Path(tempfile.mkdtemp()) / "table1"
rows = paper.reproduce("table1", out, seeds=[0, 1, 2], team_sizes=[5], iterations=40, workers=1, progress=False)
print(len(rows), "runs:", sorted({r["init"] for r in rows}))

# %%
# The rows beside the paper's numbers
# -----------------------------------
# ``table1.md`` holds the table with the paper's values; the same text is
# ``uavcov.paper._reports.table1_markdown`` of the rows.
print((out / "table1.md").read_text()[:1500])

# %%
# The bars of Table 1, by start
# -----------------------------
bars = plotting.plot_table1(rows, metric="max_coverage")
