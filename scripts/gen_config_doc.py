#!/usr/bin/env python3
"""Regenerates docs/configuration.md from `rtgi-bench --help` (the key table).
    python3 scripts/gen_config_doc.py build/rtgi-bench > docs/configuration.md"""
import re
import subprocess
import sys

out = subprocess.run([sys.argv[1], "--help"], capture_output=True, text=True, check=True).stdout
keys = out[out.index("Configuration keys"):].splitlines()[1:]
print("# Configuration keys\n")
print("Set with `--set key=value` (repeatable), `--config FILE.json` (keys as below; nested objects are dotted keys,")
print('e.g. `{"lpv": {"grid": 16}}`) or in sweep files. Unknown keys and out-of-range values are errors that name the key.')
print("`rtgi-bench --help` prints the same list; `scripts/gen_config_doc.py` regenerates this file and a unit test")
print("keeps it in step with the key table.\n")
print("Defaults are those of the code (`Settings{}`); a scene may suggest its own (e.g. `builtin:atrium` sets")
print("`ao.radius=1.0`, `builtin:cornell` a smaller LPV grid), and explicit `--set`/`--config` values win.\n")
print("| key | values | default | meaning |")
print("|---|---|---|---|")
for line in keys:
    m = re.match(r"\s+(\S+)\s+(\S+)\s+(.*) \(default: (.*)\)$", line)
    if m:
        print("| `%s` | `%s` | `%s` | %s |" % (m.group(1), m.group(2).replace("|", "\\|"),
                                           m.group(4).replace("|", "\\|"), m.group(3)))
