"""The catalogue of every stable diagnostic code — the only place codes are defined.

A code is what the plan JSON (``diagnostics[].code``), the terminal line
(``prog.mpf:7:5: warning 10763 (N60): …``) and :class:`~trcopt.errors.TrcoptError` carry. One
spelling: a controller's own alarm number where the controller has one (SINUMERIK ``10751``),
otherwise an upper-case, hyphenated code whose first word names the family:

=============  ================================================================================
family         meaning
=============  ================================================================================
``1xxxx``      SINUMERIK 840D sl alarm numbers (compensation, SAR, toolholder)
``NC-``        reading a program (every language)
``TRC-``       the compensation engine, where the controllers have no number
``SAR-``       SINUMERIK smooth approach and retraction without an alarm number
``HH-``        Heidenhain TNC errors (the TNC reports texts, not numbers)
``LCNC-``      LinuxCNC interpreter errors (the message is LinuxCNC's own text)
``TH-``        toolholder with orientation capability
``TIMING-``    time parameterisation
``SOLVER-``    optimisation problems
``VERIFY-``    the verification of a plan against the constraint model (one code per family)
(no prefix)    usage, files and outputs: ``USAGE``, ``IO``, ``CONFIG``, …
=============  ================================================================================

:class:`Code` is a string enum, so a code compares equal to its text and serialises as it.
:data:`MEANING` says when each is raised; ``docs/diagnostics.md`` is the same table for users (a
test keeps them equal). A :class:`~trcopt.errors.Diagnostic` or error with a code that is not
here is rejected when it is made.
"""

from __future__ import annotations

import enum

__all__ = ["Code", "MEANING", "family"]


class Code(enum.StrEnum):
    """Every stable diagnostic code (see the module docstring for the families)."""

    # --- SINUMERIK 840D sl alarms --------------------------------------------------------------
    ALARM_10740 = "10740"
    ALARM_10741 = "10741"
    ALARM_10742 = "10742"
    ALARM_10743 = "10743"
    ALARM_10744 = "10744"
    ALARM_10747 = "10747"
    ALARM_10748 = "10748"
    ALARM_10750 = "10750"
    ALARM_10751 = "10751"
    ALARM_10753 = "10753"
    ALARM_10754 = "10754"
    ALARM_10755 = "10755"
    ALARM_10756 = "10756"
    ALARM_10757 = "10757"
    ALARM_10758 = "10758"
    ALARM_10762 = "10762"
    ALARM_10763 = "10763"
    ALARM_10860 = "10860"
    ALARM_12550 = "12550"
    ALARM_12640 = "12640"
    ALARM_14011 = "14011"
    ALARM_14080 = "14080"
    ALARM_14153 = "14153"
    ALARM_14500 = "14500"
    # --- reading programs ------------------------------------------------------------------------
    NC_SYNTAX = "NC-SYNTAX"
    NC_UNSUPPORTED = "NC-UNSUPPORTED"
    NC_UNSUPPORTED_WORD = "NC-UNSUPPORTED-WORD"
    NC_UNSUPPORTED_EXPR = "NC-UNSUPPORTED-EXPR"
    NC_PATH_CONTROL = "NC-PATH-CONTROL"
    NC_ARC_RADIUS = "NC-ARC-RADIUS"
    NC_ARC_CENTRE = "NC-ARC-CENTRE"
    NC_DISC_CLAMPED = "NC-DISC-CLAMPED"
    NC_FEED_MODE = "NC-FEED-MODE"
    NC_NO_END = "NC-NO-END"
    NC_SAR_PARAM = "NC-SAR-PARAM"
    NC_TOOL_TYPE = "NC-TOOL-TYPE"
    NC_INTERNAL = "NC-INTERNAL"
    NC_LOOP_LIMIT = "NC-LOOP-LIMIT"
    NC_RANGE = "NC-RANGE"
    NC_NOT_TEXT = "NC-NOT-TEXT"
    NC_TOOL_RADIUS = "NC-TOOL-RADIUS"
    NC_EXPRESSION = "NC-EXPRESSION"
    NC_PARAM_UNSET = "NC-PARAM-UNSET"
    NC_FRAME = "NC-FRAME"
    NC_CALL = "NC-CALL"
    NC_CYCLE = "NC-CYCLE"
    # --- compensation engine ---------------------------------------------------------------------
    TRC_CONTOUR_VIOLATION = "TRC-CONTOUR-VIOLATION"
    TRC_SIDE_CHANGE = "TRC-SIDE-CHANGE"
    TRC_ACTIVE_AT_END = "TRC-ACTIVE-AT-END"
    TRC_KONTT_BLOCK = "TRC-KONTT-BLOCK"
    TRC_CURVE = "TRC-CURVE"
    # --- SINUMERIK SAR ---------------------------------------------------------------------------
    SAR_PREPROCESSING_STOP = "SAR-PREPROCESSING-STOP"
    # --- Heidenhain TNC --------------------------------------------------------------------------
    HH_SYNTAX = "HH-SYNTAX"
    HH_TOOL_RADIUS_TOO_LARGE = "HH-TOOL-RADIUS-TOO-LARGE"
    HH_TRC_SIDE_SWITCH = "HH-TRC-SIDE-SWITCH"
    HH_TRC_IN_CIRCLE = "HH-TRC-IN-CIRCLE"
    HH_TRC_NEG_RADIUS = "HH-TRC-NEG-RADIUS"
    HH_CIRCLE_END = "HH-CIRCLE-END"
    HH_CR_CHORD = "HH-CR-CHORD"
    HH_CT_NO_TANGENT = "HH-CT-NO-TANGENT"
    HH_RND_TOO_LARGE = "HH-RND-TOO-LARGE"
    HH_CHF_TOO_LARGE = "HH-CHF-TOO-LARGE"
    HH_CHF_NOT_LINES = "HH-CHF-NOT-LINES"
    HH_APPR_NO_CONTOUR = "HH-APPR-NO-CONTOUR"
    HH_APPR_NO_FEED = "HH-APPR-NO-FEED"
    HH_APPR_NO_TANGENT = "HH-APPR-NO-TANGENT"
    HH_APPR_CCA = "HH-APPR-CCA"
    HH_NO_FEED = "HH-NO-FEED"
    HH_NO_POLE = "HH-NO-POLE"
    HH_NO_TOOL = "HH-NO-TOOL"
    HH_TOOL_UNKNOWN = "HH-TOOL-UNKNOWN"
    HH_PARAXIAL_NOT_PARAXIAL = "HH-PARAXIAL-NOT-PARAXIAL"
    HH_APPR_RAPID = "HH-APPR-RAPID"
    HH_APPR_R0 = "HH-APPR-R0"
    HH_DEP_R0 = "HH-DEP-R0"
    HH_PGM_CALL = "HH-PGM-CALL"
    HH_TOOL_TABLE = "HH-TOOL-TABLE"
    HH_Q_UNDEFINED = "HH-Q-UNDEFINED"
    HH_Q_MATH = "HH-Q-MATH"
    HH_LABEL = "HH-LABEL"
    HH_LOOP_LIMIT = "HH-LOOP-LIMIT"
    HH_PGM_MISSING = "HH-PGM-MISSING"
    HH_FRAME = "HH-FRAME"
    HH_NOT_MODELLED = "HH-NOT-MODELLED"
    # --- LinuxCNC --------------------------------------------------------------------------------
    LCNC_TOOL_TABLE = "LCNC-TOOL-TABLE"
    LCNC_TOOL_NOT_FOUND = "LCNC-TOOL-NOT-FOUND"
    LCNC_ARC_RADIUS = "LCNC-ARC-RADIUS"
    LCNC_ENTRY_TOO_SHORT = "LCNC-ENTRY-TOO-SHORT"
    LCNC_ENTRY_ARC_TOO_SHORT = "LCNC-ENTRY-ARC-TOO-SHORT"
    LCNC_CONCAVE_GOUGE = "LCNC-CONCAVE-GOUGE"
    LCNC_CONCAVE_GOUGE_TRAVERSE = "LCNC-CONCAVE-GOUGE-TRAVERSE"
    LCNC_CONCAVE_GOUGE_ARC = "LCNC-CONCAVE-GOUGE-ARC"
    LCNC_ARC_LINE_GOUGE = "LCNC-ARC-LINE-GOUGE"
    LCNC_ARC_ARC_GOUGE = "LCNC-ARC-ARC-GOUGE"
    LCNC_ARC_SAME_CENTER = "LCNC-ARC-SAME-CENTER"
    LCNC_ARC_TOO_SMALL = "LCNC-ARC-TOO-SMALL"
    LCNC_COMP_ALREADY_ON = "LCNC-COMP-ALREADY-ON"
    LCNC_YZ_PLANE = "LCNC-YZ-PLANE"
    LCNC_ARC_AFTER_G40 = "LCNC-ARC-AFTER-G40"
    LCNC_ARC_MISMATCH = "LCNC-ARC-MISMATCH"
    LCNC_CONTROL_MODE = "LCNC-CONTROL-MODE"
    LCNC_EXPRESSION = "LCNC-EXPRESSION"
    LCNC_PARAMETER = "LCNC-PARAMETER"
    LCNC_OWORD = "LCNC-OWORD"
    LCNC_COMP_ACTIVE = "LCNC-COMP-ACTIVE"
    LCNC_CYCLE = "LCNC-CYCLE"
    LCNC_OFFSET = "LCNC-OFFSET"
    LCNC_WORDS = "LCNC-WORDS"
    LCNC_MESSAGE = "LCNC-MESSAGE"
    LCNC_ABORT = "LCNC-ABORT"
    # --- toolholder ------------------------------------------------------------------------------
    TH_VALUE = "TH-VALUE"
    TH_CHAIN_OPEN = "TH-CHAIN-OPEN"
    TH_IGNORED_L1 = "TH-IGNORED-L1"
    TH_IGNORED_L4 = "TH-IGNORED-L4"
    TH_UNDEFINED_PARAM = "TH-UNDEFINED-PARAM"
    TH_UNKNOWN_HOLDER = "TH-UNKNOWN-HOLDER"
    TH_UNKNOWN_WORD = "TH-UNKNOWN-WORD"
    TH_UNREACHABLE = "TH-UNREACHABLE"
    TH_NO_VALID_SOLUTION = "TH-NO-VALID-SOLUTION"
    TH_LIMIT = "TH-LIMIT"
    # --- timing ----------------------------------------------------------------------------------
    TIMING = "TIMING"
    TIMING_EMPTY = "TIMING-EMPTY"
    TIMING_FEED = "TIMING-FEED"
    TIMING_ZERO_LENGTH = "TIMING-ZERO-LENGTH"
    TIMING_STUCK = "TIMING-STUCK"
    TIMING_TOPPRA = "TIMING-TOPPRA"
    TIMING_JERK_GRID = "TIMING-JERK-GRID"
    TIMING_JERK_SOLVER = "TIMING-JERK-SOLVER"
    TIMING_LIMITS = "TIMING-LIMITS"
    # --- optimisation ----------------------------------------------------------------------------
    SOLVER = "SOLVER"
    SOLVER_INFEASIBLE = "SOLVER-INFEASIBLE"
    # --- verification ----------------------------------------------------------------------------
    VERIFY_RADIUS = "VERIFY-RADIUS"
    VERIFY_TANGENCY = "VERIFY-TANGENCY"
    VERIFY_CONTINUITY = "VERIFY-CONTINUITY"
    VERIFY_NO_REVERSAL = "VERIFY-NO-REVERSAL"
    VERIFY_CLEARANCE = "VERIFY-CLEARANCE"
    # --- usage, files, outputs -------------------------------------------------------------------
    TRCOPT = "TRCOPT"
    USAGE = "USAGE"
    IO = "IO"
    OUTPUT = "OUTPUT"
    MEMORY = "MEMORY"
    CONFIG = "CONFIG"
    GEOMETRY = "GEOMETRY"
    GCODE = "GCODE"
    PLAN_JSON = "PLAN-JSON"
    SCHEMA = "SCHEMA"
    DXF_MISSING = "DXF-MISSING"
    HH_M120 = "HH-M120"
    HH_NO_DIRECTION = "HH-NO-DIRECTION"


MEANING: dict[Code, str] = {
    Code.ALARM_10740: "SAR: too many blocks without plane motion between the SAR block and the contour (MD20202)",
    Code.ALARM_10741: "SAR: the infeed would reverse its direction (DISCL check)",
    Code.ALARM_10742: "SAR: DISR missing or invalid, or the lead line length / circle radius is ≤ 0",
    Code.ALARM_10743: "SAR programmed more than once in a block, or conflicting SAR words",
    Code.ALARM_10744: "SAR: no valid approach or retraction direction (e.g. a zero-length contour block)",
    Code.ALARM_10747: "SAR: retraction direction undefined (G143, or G140 without compensation, with an implicit end)",
    Code.ALARM_10748: "SAR: illegal retraction plane (DISRP)",
    Code.ALARM_10750: "G41/G42 selected without an active tool edge (T/D)",
    Code.ALARM_10751: "collision danger: no intersection found (G461/G462, unresolved inside corner, degenerate "
    "offset, or a possible contour violation under --strict)",
    Code.ALARM_10753: "compensation selected in a circular block",
    Code.ALARM_10754: "compensation deselected in a circular block",
    Code.ALARM_10755: "KONT approach impossible: the start point lies within the tool radius of the contour start",
    Code.ALARM_10756: "KONT retraction impossible: the end point lies within the tool radius of the contour end",
    Code.ALARM_10757: "plane change while compensation is active",
    Code.ALARM_10758: "curvature radius too small for the (variable) compensation value",
    Code.ALARM_10762: "too many blocks without plane motion in a row (MD20250)",
    Code.ALARM_10763: "warning: a block was omitted by bottleneck detection (CDON); the program continues",
    Code.ALARM_10860: "no feedrate programmed: a feed motion with no F in force (none programmed yet, or a change "
    "of feed type G94/G95 deleted it)",
    Code.ALARM_12550: "name not defined: a variable used without (or before) its DEF, or an unknown function",
    Code.ALARM_12640: "invalid nesting of control structures (IF/ELSE/ENDIF, WHILE, FOR, REPEAT/UNTIL, LOOP do not "
    "pair)",
    Code.ALARM_14011: "a called subprogram does not exist: no NAME.spf/.mpf in the folders searched (named in the "
    "message)",
    Code.ALARM_14080: "jump destination not found (GOTOF/GOTOB/GOTO, REPEAT labels)",
    Code.ALARM_14153: "toolholder: kinematic type other than T, P or M",
    Code.ALARM_14500: "DEF after the first executable block (definitions belong in the program header)",
    Code.NC_SYNTAX: "the program text cannot be read (bad word, number, bracket or comment)",
    Code.NC_UNSUPPORTED: "a language feature trcopt does not model (named in the message); the plan stops",
    Code.NC_UNSUPPORTED_WORD: "a word trcopt does not model; it is reported, never silently dropped",
    Code.NC_UNSUPPORTED_EXPR: "an expression trcopt cannot evaluate",
    Code.NC_PATH_CONTROL: "a path-control word trcopt does not model exactly: the message says how the corners "
    "are planned instead",
    Code.NC_ARC_RADIUS: "arc end point not on the circle within the end-radius tolerance, or a zero radius",
    Code.NC_ARC_CENTRE: "circular block without centre (I/J/K) or radius (CR=)",
    Code.NC_DISC_CLAMPED: "DISC above MD20220 was clamped",
    Code.NC_FEED_MODE: "a feed that gives no path feed: feed per revolution (G95, FAD=PR) without a spindle "
    "speed or with the spindle not turning, an inverse-time F0; the plan stops",
    Code.NC_NO_END: "warning: the program has no end (M2/M30)",
    Code.NC_SAR_PARAM: "a SAR parameter (DISR, DISCL, DISRP, FAD) has an invalid value",
    Code.NC_TOOL_TYPE: "the tool type is not a milling tool; the compensation side check does not apply",
    Code.NC_INTERNAL: "an internal error while reading a block (a bug: please report the program)",
    Code.NC_LOOP_LIMIT: "a program loop jumped back more often than the stated iteration limit: taken as endless",
    Code.NC_RANGE: "a number out of range: not finite, or a coordinate, radius or feed beyond the bounds of "
    "trcopt.nc.limits (|coordinate| ≤ 1e5 mm, feed ≤ 1e8 mm/min, ≤ 1e4 turns)",
    Code.NC_NOT_TEXT: "the program file is not a text file (NUL bytes or undecodable binary content)",
    Code.NC_TOOL_RADIUS: "a negative tool radius ($TC_DP6, Heidenhain TOOL DEF R or tool-table R)",
    Code.NC_EXPRESSION: "an expression cannot be evaluated: division by zero, a function argument outside its "
    "domain (SQRT of a negative number, ASIN(2), TAN(90)), a result that is not finite",
    Code.NC_PARAM_UNSET: "an R-parameter is read before the program sets it (its value on the machine is unknown)",
    Code.NC_FRAME: "a frame or zero offset trcopt cannot plan: a scale factor 0, a rotation that tilts the working "
    "plane, a circle under a non-uniform scale, or machine coordinates / a change of zero offset without the "
    "zero-offset file",
    Code.NC_CALL: "a subprogram call that cannot run: too many arguments, more than 16 program levels, a misplaced "
    "PROC",
    Code.NC_CYCLE: "a drilling cycle (CYCLE81-83) with missing or inconsistent values, or a parameter trcopt does "
    "not model",
    Code.TRC_CONTOUR_VIOLATION: "warning: a CDOF offset runs against its programmed element (possible contour "
    "violation); --strict makes it alarm 10751",
    Code.TRC_SIDE_CHANGE: "compensation side changed (G41↔G42) without deselecting first",
    Code.TRC_ACTIVE_AT_END: "warning: the program ends with compensation still on",
    Code.TRC_KONTT_BLOCK: "KONTT/KONTC needs a linear approach block in the plane",
    Code.TRC_CURVE: "a KONTT/KONTC polynomial or DISC transition needs more samples than "
    "trcopt.geometry.poly.MAX_CURVE_SAMPLES (a degenerate or extreme curve)",
    Code.SAR_PREPROCESSING_STOP: "a preprocessing stop between a SAR block and its tangent block (no alarm number "
    "in the manuals)",
    Code.HH_SYNTAX: "a Klartext block or APPR/DEP parameter cannot be read",
    Code.HH_TOOL_RADIUS_TOO_LARGE: "Heidenhain \"Tool radius too large\": an offset element reverses or vanishes, or "
    "an APPR/DEP arc is too small",
    Code.HH_TRC_SIDE_SWITCH: "RL↔RR changed without an R0 block",
    Code.HH_TRC_IN_CIRCLE: "radius compensation switched on or off in a circle block",
    Code.HH_TRC_NEG_RADIUS: "negative compensation value (R + DR_TAB + DR_CALL < 0)",
    Code.HH_CIRCLE_END: "C: the end point is not on the circle about CC",
    Code.HH_CR_CHORD: "CR: the chord is longer than the diameter, or start and end coincide",
    Code.HH_CT_NO_TANGENT: "CT without a preceding element, or the end point on its tangent",
    Code.HH_RND_TOO_LARGE: "RND radius invalid or longer than a neighbouring element allows",
    Code.HH_CHF_TOO_LARGE: "CHF length invalid or longer than a neighbouring line",
    Code.HH_CHF_NOT_LINES: "CHF between elements that are not both straight lines",
    Code.HH_APPR_NO_CONTOUR: "APPR without a following contour element",
    Code.HH_APPR_NO_FEED: "APPR LCT without a programmed feed rate",
    Code.HH_APPR_NO_TANGENT: "APPR/DEP: the auxiliary point lies inside the tool-centre circle (no tangent)",
    Code.HH_APPR_CCA: "APPR/DEP CT: centre angle CCA outside (0°, 360°]",
    Code.HH_NO_FEED: "FAUTO without a feed in TOOL CALL",
    Code.HH_NO_POLE: "polar coordinates without a pole (CC)",
    Code.HH_NO_TOOL: "radius compensation without a TOOL CALL",
    Code.HH_TOOL_UNKNOWN: "TOOL CALL of a tool that is not in the tool table",
    Code.HH_PARAXIAL_NOT_PARAXIAL: "R+/R− in a block with more than one plane coordinate",
    Code.HH_APPR_RAPID: "warning: the APPR leg PS→PH is traversed at FMAX (the last positioning was FMAX)",
    Code.HH_APPR_R0: "warning: APPR with R0: the lead is computed with radius 0 on side RR (iTNC 530)",
    Code.HH_DEP_R0: "warning: DEP without radius compensation: computed with radius 0 on side RR",
    Code.HH_PGM_CALL: "warning: CALL PGM while RL/RR is active: compensation is cancelled at the call",
    Code.HH_TOOL_TABLE: "warning: the tool table beside the program could not be read and is ignored",
    Code.HH_Q_UNDEFINED: "a Q parameter is read before a value was assigned to it",
    Code.HH_Q_MATH: "Q-parameter arithmetic impossible: division by zero, root of a negative number, "
    "result out of range",
    Code.HH_LABEL: "jump or call to a label that is not in the program, a label defined twice, LBL 0 outside a call",
    Code.HH_LOOP_LIMIT: "the program does not end within the executed-block limit, or calls nest too deep",
    Code.HH_PGM_MISSING: "CALL PGM: the called program file is not beside the calling program",
    Code.HH_FRAME: "a coordinate transformation cycle (CYCL DEF 7/8/10/11/26) is invalid: scale 0, degenerate plane",
    Code.HH_NOT_MODELLED: "a word that changes motion or control flow and is not modelled by trcopt",
    Code.LCNC_TOOL_TABLE: "note: which tool table was read, in which unit",
    Code.LCNC_TOOL_NOT_FOUND: "the requested tool is not in the tool table",
    Code.LCNC_ARC_RADIUS: "an R-format arc whose radius cannot reach its end point",
    Code.LCNC_ENTRY_TOO_SHORT: "the compensation entry move is not longer than the tool radius",
    Code.LCNC_ENTRY_ARC_TOO_SHORT: "the compensation entry arc radius is not greater than the tool radius",
    Code.LCNC_CONCAVE_GOUGE: "straight feed into a concave corner the tool cannot reach without gouging",
    Code.LCNC_CONCAVE_GOUGE_TRAVERSE: "straight traverse into a concave corner the tool cannot reach without gouging",
    Code.LCNC_CONCAVE_GOUGE_ARC: "arc move into a concave corner the tool cannot reach without gouging",
    Code.LCNC_ARC_LINE_GOUGE: "arc-to-line corner the compensated tool cannot fit in without gouging",
    Code.LCNC_ARC_ARC_GOUGE: "arc-to-arc corner the compensated tool cannot fit in without gouging",
    Code.LCNC_ARC_SAME_CENTER: "arc-to-arc motion between arcs with the same centre",
    Code.LCNC_ARC_TOO_SMALL: "tool radius not less than the arc radius with compensation",
    Code.LCNC_COMP_ALREADY_ON: "compensation turned on while already on",
    Code.LCNC_YZ_PLANE: "compensation in the YZ plane (G19)",
    Code.LCNC_ARC_AFTER_G40: "the move right after G40 is an arc",
    Code.LCNC_ARC_MISMATCH: "an inside corner moves the end of a queued arc off its circle (LinuxCNC's internal "
    "check, after an entry arc)",
    Code.LCNC_CONTROL_MODE: "G61/G61.1/G64 while cutter radius compensation is on",
    Code.LCNC_EXPRESSION: "an expression LinuxCNC cannot evaluate (division by zero, a function argument out of "
    "range, not a number)",
    Code.LCNC_PARAMETER: "a parameter LinuxCNC cannot read: a named parameter never set, a number out of range",
    Code.LCNC_OWORD: "O-word control flow: an unknown or unclosed subroutine, a label without its if/while/do, "
    "a duplicate label, too many call levels",
    Code.LCNC_COMP_ACTIVE: "a block LinuxCNC refuses while cutter radius compensation is on: a change of work "
    "offset, G92, tool, tool length offset, plane or units, G53, G28/G30, a canned cycle",
    Code.LCNC_CYCLE: "a canned cycle LinuxCNC rejects: R or the depth missing, R below the bottom, a missing "
    "P/Q/I/J/K, zero repeats, the spindle not turning, inverse time feed (G93)",
    Code.LCNC_OFFSET: "G10/G92/G53 LinuxCNC rejects: a P or L out of range, axes missing, G53 incremental or "
    "without G0/G1",
    Code.LCNC_WORDS: "a word combination LinuxCNC rejects: two G or M codes of one modal group, axis words without a "
    "G code using them, a D, H, L, P, Q or R word nothing uses, a feed move at zero feed, at zero spindle speed "
    "under G95 or without F under G93",
    Code.LCNC_MESSAGE: "note: a (MSG,…), (DEBUG,…) or (PRINT,…) comment, with its parameters substituted",
    Code.LCNC_ABORT: "the program aborts with its (ABORT,…) message",
    Code.TH_VALUE: "a $TC_CARR value is invalid",
    Code.TH_CHAIN_OPEN: "warning: the toolholder's kinematic chain does not close",
    Code.TH_IGNORED_L1: "warning: l1 is ignored for a type P toolholder",
    Code.TH_IGNORED_L4: "warning: l4 is ignored for a type T toolholder",
    Code.TH_UNDEFINED_PARAM: "a $TC_CARR parameter the toolholder needs is not defined",
    Code.TH_UNKNOWN_HOLDER: "TCARR selects a toolholder that is not defined",
    Code.TH_UNKNOWN_WORD: "an orientation word trcopt does not model",
    Code.TH_UNREACHABLE: "the requested orientation cannot be reached by the toolholder",
    Code.TH_NO_VALID_SOLUTION: "no solution of the toolholder lies within its limits",
    Code.TH_LIMIT: "a toolholder angle lies outside its software limits",
    Code.TIMING: "the time parameterisation failed (section, arc length and block in the message)",
    Code.TIMING_EMPTY: "nothing to time (empty tool path)",
    Code.TIMING_FEED: "a segment has no usable feed",
    Code.TIMING_ZERO_LENGTH: "a zero-length segment cannot be timed",
    Code.TIMING_STUCK: "the reachability solver made no progress along a section",
    Code.TIMING_TOPPRA: "toppra failed on a polynomial section",
    Code.TIMING_JERK_GRID: "the jerk-limited problem of a section has a degenerate grid",
    Code.TIMING_JERK_SOLVER: "IPOPT failed on a jerk-limited section (the acceleration-limited feed is kept)",
    Code.TIMING_LIMITS: "the acceleration-limited feed, re-checked between its grid points, exceeds a machine limit",
    Code.SOLVER: "an optimisation problem failed",
    Code.SOLVER_INFEASIBLE: "an optimisation problem is infeasible (the binding constraint is named)",
    Code.VERIFY_RADIUS: "warning (--strict: error): a compensated tool-centre element is not at the tool radius "
    "from its programmed element",
    Code.VERIFY_TANGENCY: "warning (--strict: error): a tool-centre joint that must be tangent is not, or an "
    "offset element runs against its programmed element",
    Code.VERIFY_CONTINUITY: "warning (--strict: error): consecutive tool-centre segments do not meet",
    Code.VERIFY_NO_REVERSAL: "warning (--strict: error): the infeed reverses its direction during an approach or "
    "retraction",
    Code.VERIFY_CLEARANCE: "warning (--strict: error): the tool comes closer than its radius to the part contour "
    "(a gouge; lead-in/out blocks and approach/retraction moves are not part contour)",
    Code.TRCOPT: "an error without a more specific code",
    Code.USAGE: "a command-line or API argument is invalid (the valid options are listed)",
    Code.IO: "a file cannot be read",
    Code.OUTPUT: "an output file cannot be written (nothing is left half-written)",
    Code.MEMORY: "the plan needs more memory than the machine has (nothing is written)",
    Code.CONFIG: "a machine, tool-table or settings file is invalid (the key is named)",
    Code.GEOMETRY: "invalid geometry (zero-length element, inconsistent arc)",
    Code.GCODE: "a G-code writer option is invalid or a segment cannot be written",
    Code.PLAN_JSON: "the plan JSON cannot be written (e.g. a non-finite number)",
    Code.SCHEMA: "a plan JSON document does not follow the schema",
    Code.DXF_MISSING: "DXF export needs the optional package ezdxf (pip install 'trcopt[dxf]')",
    Code.HH_M120: "M120 LA (radius-compensated look-ahead) programmed where the TNC refuses it: LA not a whole "
    "number 0…99, LA without M120, M120 LA without RL/RR or outside a positioning block, a cycle that needs "
    "M120 cancelled",
    Code.HH_NO_DIRECTION: "RND, CT, APPR or DEP needs the direction of a neighbouring contour element that does "
    "not move in the working plane (a null or an infeed-only move)",
}

_FAMILIES = {
    "NC": "reading programs",
    "TRC": "compensation",
    "SAR": "SINUMERIK SAR",
    "HH": "Heidenhain TNC",
    "LCNC": "LinuxCNC",
    "TH": "toolholder",
    "TIMING": "timing",
    "SOLVER": "optimisation",
    "VERIFY": "verification",
}


def family(code: Code | str) -> str:
    """The family a code belongs to (the table of the module docstring)."""
    text = str(Code(code))
    if text.isdigit():
        return "SINUMERIK alarm"
    return _FAMILIES.get(text.split("-", 1)[0], "usage, files and outputs")
