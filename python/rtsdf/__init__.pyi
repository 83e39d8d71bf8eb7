"""rtsdf: signed distance fields of triangle-mesh scenes. The package re-exports its native module (_rtsdf.pyi
types it); names the package adds in Python are typed here beside it."""
from ._rtsdf import *
