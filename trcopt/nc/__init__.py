"""The dialect-neutral layer of the NC front end.

* :mod:`.model` — the canonical :class:`Move` and :class:`NcProgram` every controller's reader
  produces (absolute mm, feeds in mm/s, the modal snapshot compensation needs, source spans);
* :mod:`.modal` — the modal state shared by the readers and the closed-form helpers they must not
  get wrong (arc centre from a radius, end-radius check);
* :mod:`.tools` — tool edges and the tool table a program reads.

Reading a program is the job of a controller: :func:`trcopt.controllers.read_program`.
"""

from trcopt.nc.modal import ModalState, ReadOptions
from trcopt.nc.model import CompState, Move, MoveKind, NcProgram, SarSpec
from trcopt.nc.tools import ToolEdge, ToolTable

__all__ = [
    "CompState",
    "ModalState",
    "Move",
    "MoveKind",
    "NcProgram",
    "ReadOptions",
    "SarSpec",
    "ToolEdge",
    "ToolTable",
]
