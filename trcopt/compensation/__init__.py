"""Tool radius compensation: the shared engine and its controller profiles.

* :mod:`.engine` — the streaming driver: :func:`compensate`, :class:`Compensator`,
  :func:`programmed_segment`;
* :mod:`.junctions` — how each block ends: the corner rules, the predictive and backward searches,
  the strategy extension of an unresolved first or last corner, CDON bottleneck detection;
* :mod:`.selection` — the junctions of the selection and deselection blocks (NORM, KONT, KONTT,
  KONTC) and the G461/G462 auxiliary elements;
* :mod:`.lookahead` — the look-ahead window, the record of a resolved junction, the chain searches;
* :mod:`.corners` — junction geometry: classification, transition circle, DISC conic,
  intersection, approach/retraction polynomials;
* :mod:`.elements` — compensated elements and the pieces of their tool-centre chains;
* :mod:`.leads` — the SINUMERIK SAR lead geometry P0…P4;
* :mod:`.profiles` — a controller's compensation semantics as data over the engine.
"""

from trcopt.compensation.engine import Compensator, compensate, programmed_segment

__all__ = ["Compensator", "compensate", "programmed_segment"]
