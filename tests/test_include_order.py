"""The pipeline the src/ folders show, enforced on their internal headers:
each folder may include the internal headers of the folders before it in
STAGES (and its own), never of one after it, so there is no wrong-way
arrow and no circle between folders. A folder that is not in STAGES, and an
internal header that two folders define, fail too. (The public headers in
include/railride/ are not checked here yet.)"""
import os
import re
import sys

sys.path.insert(0, os.path.dirname(__file__))
from pycheck import check, done  # noqa: E402

STAGES = ["util", "linalg", "vehicle", "contact", "model", "modal", "ride", "vertical",
          "timedomain", "nonlinear", "optimise"]
src = os.path.join(os.environ.get("RR_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..")), "src")
folders = sorted(d for d in os.listdir(src) if os.path.isdir(os.path.join(src, d)))
check(folders == sorted(STAGES), "src/ has exactly the stages %s: %s" % (STAGES, folders))
owner = {}
for d in folders:
    for f in os.listdir(os.path.join(src, d)):
        if f.endswith(".h"):
            check(f not in owner, "%s is defined once (%s, %s)" % (f, owner.get(f), d))
            owner[f] = d
rank = {d: i for i, d in enumerate(STAGES)}
arrows = 0
for d in folders:
    for f in sorted(os.listdir(os.path.join(src, d))):
        if not f.endswith((".c", ".h")):
            continue
        for n, line in enumerate(open(os.path.join(src, d, f), errors="replace"), 1):
            m = re.match(r'\s*#\s*include\s+"([^"/]+)"', line)
            if not m or m.group(1) not in owner:
                continue
            to = owner[m.group(1)]
            arrows += 1
            check(rank.get(to, 99) <= rank.get(d, -1),
                  "src/%s/%s:%d includes %s of %s/, a later stage" % (d, f, n, m.group(1), to))
check(arrows > 50, "the internal includes were read (%d)" % arrows)
done("include order")
