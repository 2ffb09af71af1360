"""The registry knows every controller without loading their readers: a program of one controller
loads that controller's reader and compensation only (a short run's start-up is mostly imports)."""

import subprocess
import sys
import textwrap

READERS = {
    "siemens": "trcopt.controllers.siemens.reader",
    "heidenhain": "trcopt.controllers.heidenhain.reader",
    "linuxcnc": "trcopt.controllers.linuxcnc.reader",
}

PROGRAMS = {
    "siemens": ("p.mpf", "N10 G0 X0 Y0\nN20 G1 X10 F100\nN30 M30\n"),
    "heidenhain": ("p.h", "0 BEGIN PGM P MM\n1 L X+0 Y+0 FMAX\n2 L X+10 F100\n3 END PGM P MM\n"),
    "linuxcnc": ("p.ngc", "G21 G90\nG0 X0 Y0\nG1 X10 F100\nM2\n"),
}


def _loaded_after(code: str) -> set[str]:
    script = textwrap.dedent(code) + "\nimport sys\nprint('\\n'.join(sorted(sys.modules)))\n"
    out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, check=True)
    return set(out.stdout.split())


def test_registry_loads_no_reader():
    loaded = _loaded_after("import trcopt.controllers as c\nassert c.names() and c.detect('x.h', '')")
    assert not loaded & set(READERS.values())


def test_a_plan_loads_only_its_controller(tmp_path):
    for name, (file, text) in PROGRAMS.items():
        path = tmp_path / file
        path.write_text(text)
        loaded = _loaded_after(
            f"from trcopt.pipeline import PlanOptions, plan_file\n"
            f"r = plan_file({str(path)!r}, PlanOptions(timing=False))\nassert r.ok, r.diagnostics\n"
        )
        assert READERS[name] in loaded
        others = {m for other, m in READERS.items() if other != name}
        assert not loaded & others, (name, loaded & others)
        # np.median and np.unique would load numpy.ma (a few ms of a short run) on their first call
        assert "numpy.ma" not in loaded, name


def test_controllers_with_deferred_stages_pickle():
    import pickle

    from trcopt import controllers

    for name in ("siemens", "linuxcnc"):
        c = pickle.loads(pickle.dumps(controllers.get(name)))
        assert c.name == name and callable(c.read) and callable(c.compensate)


def test_a_plan_without_gcode_does_not_load_the_writers(tmp_path):
    file, text = PROGRAMS["linuxcnc"]
    path = tmp_path / file
    path.write_text(text)
    run = f"from trcopt.cli import main\nassert main(['plan', {str(path)!r}, '--no-timing', '-q']) == 0\n"
    loaded = _loaded_after(run)
    assert "trcopt.io.gcode_program" not in loaded and "trcopt.io.klartext" not in loaded
