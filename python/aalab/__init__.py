"""aalab: a Python client of the aalab daemon (evaluate, optimize and render antialiasing sample
patterns), point-set files (:mod:`aalab.formats`) and figures (:mod:`aalab.plot`, matplotlib).

Quick start::

    import aalab
    c = aalab.Client()                         # finds the socket as the aalab command does
    print(c.evaluate("rgss").e2)               # 0.439 (Laine & Aila Table 2)
    job = c.optimize(family="P(4,1+,2)", seeds=4, max_iterations=200).wait()
    print(job.best_e2, job.trace.best_e2[-1])

Conventions: E2 is dimensionless; angles are in degrees; run times are seconds of the job's own
clock. Wire-form coordinates are pixels, x right and y up (kernels relative to the output point,
the pixel [-0.5, 0.5]²); point files use the unit square of the whole tile
(:mod:`aalab.formats`). The standard library is the only requirement; numpy gives arrays,
tqdm progress bars, Pillow decoded tiles, matplotlib the plots, jsonschema answer validation.
Importing the package does not connect to anything.
"""

from .client import JOB_STATES, Client
from .errors import AalabError, DaemonUnreachable
from .formats import FormatError, PointSet
from .job import ENDED, Job
from .patterns import as_pattern
from .results import (Analysis, Argmax, Enumeration, Evaluation, PointMetrics, Render, Spearman,
                      Trace)
from . import temporal  # the module: aalab.temporal.temporal(...), .halton(...)
from .temporal import TemporalArgmax, TemporalEvaluation
from .tables import ResultTable, result_table

# The version is aalab's one version, CMakeLists.txt project(VERSION), which setup.py gives the
# package's metadata; "unknown" when the package is imported from a source tree, uninstalled.
try:
    from importlib.metadata import PackageNotFoundError, version as _version

    __version__ = _version("aalab")
except PackageNotFoundError:
    __version__ = "unknown"

pattern = as_pattern


def __getattr__(name: str):
    # aalab.plot imports matplotlib: loaded on first use, so that "import aalab" needs nothing
    # beyond the standard library.
    if name == "plot":
        import importlib
        return importlib.import_module(".plot", __name__)
    raise AttributeError("module 'aalab' has no attribute %r" % name)

__all__ = ["Client", "Job", "AalabError", "DaemonUnreachable", "FormatError", "PointSet",
           "Evaluation", "Analysis", "PointMetrics", "Spearman", "Render", "Trace", "Enumeration",
           "Argmax", "as_pattern", "pattern",
           "TemporalEvaluation", "TemporalArgmax", "temporal", "JOB_STATES", "ENDED", "ResultTable",
           "result_table", "__version__"]
