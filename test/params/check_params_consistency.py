#!/usr/bin/env python3
"""Defaults must agree between the four places a user meets them: the core's Params struct
(include/ring_curvature/params.hpp, the single source of truth), the dynamic_reconfigure
definition (cfg/RingCurvature.cfg), the documented parameter file (config/ring_curvature.yaml)
and the README's parameter reference (a row per field, with its default). Prints one line per
check and ends with "N passed, N failed"."""
import re
import sys
from pathlib import Path

root = Path(__file__).resolve().parents[2]
hpp = (root / "include/ring_curvature/params.hpp").read_text()
cfg = (root / "cfg/RingCurvature.cfg").read_text()
yaml_text = (root / "config/ring_curvature.yaml").read_text()
readme = (root / "README.md").read_text()

enums = {}  # enum type -> {member: value}
for m in re.finditer(r"enum class (\w+) : int\s*\{(.*?)\};", hpp, re.S):
    enums[m.group(1)] = {k: int(v) for k, v in re.findall(r"(\w+) = (\d+)", m.group(2))}

struct = hpp[hpp.index("struct Params"):]
params = {}  # name -> (type, default as python value)
types = "|".join(["int", "float", "bool", "std::string"] + sorted(enums))
for typ, name, val in re.findall(r"^\s+(" + types + r") (\w+) = ([^;]+);", struct, re.M):
    if typ == "std::string":
        params[name] = (typ, val.strip().strip('"'))
    elif typ == "bool":
        params[name] = (typ, val.strip() == "true")
    elif typ in ("int",):
        params[name] = (typ, int(val))
    elif typ == "float":
        params[name] = (typ, float(val.rstrip("f")))
    else:
        member = val.split("::")[1].strip()
        params[name] = (typ, member)

results = []
def check(ok, what):
    results.append(ok)
    print(("ok   " if ok else "FAIL ") + what)

# cfg: gen.add("name", type, level, "desc", default, ...)
for name, default in re.findall(r'gen\.add\("(\w+)",\s*\w+,\s*\d+,\s*"[^"]*",\s*([^,\)]+)', cfg):
    if name not in params:
        check(False, f"cfg key '{name}' is not a field of Params")
        continue
    typ, want = params[name]
    d = default.strip()
    if typ == "bool":
        got = d == "True"
    elif typ in enums:
        got = {v: k for k, v in enums[typ].items()}.get(int(d))
    else:
        got = float(d)
        want = float(want)
    check(got == want if not isinstance(want, float) else abs(got - want) < 1e-9,
          f"cfg default of '{name}' ({d}) equals Params ({params[name][1]})")

def same(text, typ, want):
    """Whether a default as written (yaml value, README cell) equals the Params default."""
    text = text.strip("'\"")
    if typ == "bool":
        return text.lower() == str(want).lower()
    if typ in enums:
        return text == want.lower()
    if typ == "std::string":
        return text == want
    try:
        return abs(float(text) - float(want)) < 1e-6
    except ValueError:
        return False


# yaml: key: value  # comment ; every Params field documented with its default
yaml = {}
for line in yaml_text.splitlines():
    m = re.match(r"^(\w+):\s*([^#\s]+)\s*(#.*)?$", line)
    if m:
        yaml[m.group(1)] = (m.group(2), m.group(3))
for name, (typ, want) in params.items():
    if name not in yaml:
        check(False, f"Params field '{name}' missing from config/ring_curvature.yaml")
        continue
    v, comment = yaml[name]
    ok = same(v, typ, want)
    check(ok and bool(comment), f"yaml '{name}: {v}' equals Params ({params[name][1]}) and has a comment")

# README: the "Parameter reference" table, | `key` | `default` | meaning |
section = readme[readme.index("### Parameter reference"):]
section = section[:section.index("\n## ")]
rows = dict(re.findall(r"^\| `(\w+)` \| `([^`]*)` \|", section, re.M))
for name, (typ, want) in params.items():
    if name not in rows:
        check(False, f"Params field '{name}' missing from the README's parameter reference")
        continue
    check(same(rows[name], typ, want), f"README default of '{name}' ({rows[name]}) equals Params ({want})")

passed = sum(results)
print(f"{passed} passed, {len(results) - passed} failed")
sys.exit(0 if all(results) else 1)
