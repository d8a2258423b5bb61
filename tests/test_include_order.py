"""The pipeline the src/ folders show, enforced on every include.

The stages and their order are CMakeLists.txt's RR_STAGES (the build gives
each stage a view of src/ holding only the stages up to it, so a wrong-way
internal include already fails to compile; this test says which line, and
covers what the build cannot: the public headers). Checked:
- src/ has exactly the stages; internal headers are included by folder
  ("model/model_impl.h"), never by bare name, and exist;
- an internal include names a stage at or before the includer's;
- every public header in include/railride/ belongs to a stage (PUBLIC below),
  and a source or public header includes only public headers of stages at
  or before its own.
All arrows run down a total order, so there is no circle between folders;
tools/file-circles finds none between the files of a folder either (src/'s
stages and cli/)."""
import os
import re
import subprocess
import sys

sys.path.insert(0, os.path.dirname(__file__))
from pycheck import check, done  # noqa: E402

root = os.environ.get("RR_SOURCE_DIR", os.path.join(os.path.dirname(__file__), ".."))
src = os.path.join(root, "src")
cm = open(os.path.join(root, "CMakeLists.txt")).read()
STAGES = re.search(r"set\(RR_STAGES ([^)]*)\)", cm).group(1).split()
rank = {d: i for i, d in enumerate(STAGES)}
# Each public header's stage: the folder that defines its types and functions.
PUBLIC = {
    "common": "util", "error": "util", "units": "util", "version": "util",
    "expm": "linalg",
    "vehicle": "vehicle", "profile": "vehicle", "sdf": "vehicle",
    "contact": "contact",
    "system": "model", "model": "model", "damper": "model",
    "modal": "modal", "stability": "modal",
    "spectrum": "ride", "pem": "ride", "comfort": "ride", "ride": "ride",
    "timesim": "timedomain",
    "vertical": "vertical",
    "nonlinear": "nonlinear",
    "design": "optimise", "nsga2": "optimise", "problem": "optimise",
    "layout": "bindings", "railride": "bindings",
}
folders = sorted(d for d in os.listdir(src) if os.path.isdir(os.path.join(src, d)))
check(folders == sorted(STAGES), "src/ has exactly the stages %s: %s" % (STAGES, folders))
pubdir = os.path.join(root, "include", "railride")
pubs = sorted(f[:-2] for f in os.listdir(pubdir) if f.endswith(".h"))
check(set(pubs) <= set(PUBLIC), "every public header has a stage: %s" % sorted(set(pubs) - set(PUBLIC)))
check(all(PUBLIC[p] in rank for p in PUBLIC), "the public headers' stages are stages")

arrows = {"internal": 0, "public": 0}


def scan(path, label, stage):
    for n, line in enumerate(open(path, errors="replace"), 1):
        m = re.match(r'\s*#\s*include\s+"([^"]+)"', line)
        if not m:
            continue
        inc = m.group(1)
        where = "%s:%d" % (label, n)
        if inc.startswith("railride/"):
            name = inc[len("railride/"):-2]
            if name not in PUBLIC:  # version.h is generated; anything else is unknown
                check(name == "version" or name in pubs, "%s: %s is a public header" % (where, inc))
                continue
            arrows["public"] += 1
            check(rank[PUBLIC[name]] <= rank[stage],
                  "%s includes %s of %s/, a later stage than %s/" % (where, inc, PUBLIC[name], stage))
        elif "/" in inc:
            to = inc.split("/")[0]
            arrows["internal"] += 1
            check(to in rank and os.path.exists(os.path.join(src, inc)), "%s: %s exists" % (where, inc))
            check(rank.get(to, 99) <= rank[stage],
                  "%s includes %s of %s/, a later stage than %s/" % (where, inc, to, stage))
        elif label.startswith("src/"):
            check(not os.path.exists(os.path.join(src, stage, inc)),
                  "%s: the internal header %s is included by folder (\"%s/%s\")" % (where, inc, stage, inc))


for d in folders:
    for f in sorted(os.listdir(os.path.join(src, d))):
        if f.endswith((".c", ".h")):
            scan(os.path.join(src, d, f), "src/%s/%s" % (d, f), d)
for p in pubs:
    if p in PUBLIC:
        scan(os.path.join(pubdir, p + ".h"), "include/railride/%s.h" % p, PUBLIC[p])
check(arrows["internal"] > 50 and arrows["public"] > 100,
      "the includes were read (%d internal, %d public)" % (arrows["internal"], arrows["public"]))
fc = subprocess.run([sys.executable, os.path.join(root, "tools", "file-circles")],
                    capture_output=True, text=True)
check(fc.returncode == 0 and " 0 circles" in fc.stdout, "no two files of a folder call each other: %s"
      % fc.stdout.strip())
done("include order")
