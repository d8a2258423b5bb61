"""Every command accepts every option its --help lists, refuses the options
of other commands that it does not list, and refuses an option given twice:
no option is taken and ignored. An option is tried as `CMD OPTION VALUE
--help`: the parser meets the option before --help, so a refusal shows as
its message, and nothing runs."""
import os
import re
import subprocess
import sys
import tempfile

from pycheck import check, done  # tests/pycheck.py

cli = os.environ["RR_CLI"]

# a plausible value for each option that takes one (the test is of the
# option's acceptance, not of the value)
VALUES = {"speed": "350", "conicity": "0.17", "fmax": "10", "wmin": "0.001", "rmax": "0.5",
          "sdf": "none", "spectrum": "wuhan-guangzhou", "points": "0", "floor-height": "1.2",
          "band": "0.3:30:40", "method": "modal", "psd": "/dev/null", "over": "speed",
          "range": "100:200:3", "speeds": "100:200:3", "conicities": "0.1:0.2:2", "limit": "10",
          "vmin": "100", "vmax": "200", "step": "1", "n-conicity": "8", "x": "conicity=0.1:0.2:2",
          "y": "speed=100:200:2", "objective": "index@350", "population": "8", "generations": "1",
          "seed": "1", "threads": "1", "output": "/tmp/rr_opt_test", "duration": "1", "fs": "100",
          "k": "1e6", "c": "1e4", "freqs": "0.1:10:5", "element": "yaw", "plot": "/tmp/x.svg",
          "roll": "none", "y-range": "-1:1:0.5", "amplitudes": "3", "rail-gmp": "auto", "radius": "460",
          "radius-right": "460", "radius-left": "460", "inclination": "1/40", "gauge": "1435",
          "flange-back": "1360", "wheel-origin": "70", "gmp-depth": "14", "lateral-offset": "0", "e0": "750",
          "grid": "g.csv", "wheel": "w.dat", "wheel-left": "w.dat", "wheel-right": "w.dat", "rail": "r.dat",
          "rail-left": "r.dat", "rail-right": "r.dat", "wheels": "w.dat", "plot-data": "p.dat",
          "direction": "lateral", "outside": "extend", "vertical-spectrum": "tbt3352-vertical", "window": "5",
          "ax-p95": "0", "ax-p50": "0", "track-amplitudes": "gaussian", "hp": "1.2", "lateral-wd-p95": "0.1",
          "lateral-wd-rms": "0.1"}


scratch = tempfile.mkdtemp(prefix="rr_opts_")  # the commands' working folder: nothing may appear in it


def run(*args):
    r = subprocess.run([cli, *args], capture_output=True, text=True, timeout=60, cwd=scratch)
    return r.returncode, r.stdout + r.stderr


def options_of(cmd):
    """Option names in the command's help, and whether each takes a value."""
    _, text = run(cmd, "--help")
    opts = {}
    for line in text.splitlines():
        m = re.match(r"^  (--[a-z][a-z0-9-]*)(,\s*(--[a-z][a-z0-9-]*))?(\s+([A-Z][A-Z0-9_:=.,\[\]|-]*))?", line)
        if not m:
            continue
        takes = bool(m.group(5)) and not m.group(5).startswith("[")
        for g in (m.group(1), m.group(3)):
            if g:
                opts[g] = takes
    return opts


REFUSED = re.compile(r"unknown option|unknown argument|not one this command reads|given twice|"
                     r"not an option of this command|not written in full")
# values an option of one command needs
CMD_VALUES = {("validate", "nseg"): "1024", ("simulate", "disturbance"): "0.001",
              ("bifurcation", "speeds"): "100:200", ("bifurcation", "method"): "scan"}


def takes_value(cmd, opt):
    """Probed: an option that takes a value swallows the --help after it."""
    rc, out = run(cmd, opt, "--help")
    return "needs a value" in out or "'--help'" in out or rc != 0 and not REFUSED.search(out)


def value(cmd, name):
    return CMD_VALUES.get((cmd, name), VALUES.get(name, "1"))

_, top = run("--help")
commands = [l.split()[0] for l in top.splitlines() if re.match(r"^  [a-z]", l)]
check(len(commands) >= 15, "the command list: %s" % commands)
allopts = {}
per = {}
for cmd in commands:
    per[cmd] = options_of(cmd)
    check(len(per[cmd]) >= 1 or cmd in ("keys", "objectives"), "%s --help lists options" % cmd)
    allopts.update(per[cmd])
for cmd in commands:
    for opt in per[cmd]:
        if opt in ("--help", "--plot", "--plot-script"):  # main's, around the command (test_plots.sh)
            continue
        one = [opt] + ([value(cmd, opt[2:])] if takes_value(cmd, opt) else [])
        rc, out = run(cmd, *one, "--help")
        check(rc == 0 and not REFUSED.search(out), "%s accepts its own %s: %s" % (cmd, opt, out.strip()[-200:]))
        rc, out = run(cmd, *one, *one, "--help")
        check(rc == 2 and "twice" in out, "%s refuses %s given twice: %s" % (cmd, opt, out.strip()[-200:]))
        if len(opt) > 4 and opt[:-1] not in per[cmd]:  # a prefix of the name is not taken for it (unless it is an option of its own: --profile, --profiles)
            rc, out = run(cmd, opt[:-1], *one[1:], "--help")
            check(rc == 2 and REFUSED.search(out), "%s refuses %s for %s: %s" % (cmd, opt[:-1], opt, out.strip()[-200:]))
    for opt in allopts:
        if opt in per[cmd] or opt in ("--plot", "--plot-script", "--help"):
            continue
        rc, out = run(cmd, opt, value(cmd, opt[2:]), "--help")
        check(rc == 2 and REFUSED.search(out), "%s refuses %s, another command's option: rc %d %s"
              % (cmd, opt, rc, out.strip()[-200:]))
left = os.listdir(scratch)
check(not left, "an option tried with --help wrote files: %s" % left)
done("options")
