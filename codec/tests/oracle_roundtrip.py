#!/usr/bin/env python3
"""Reads UPER MessageFrames as hex lines on stdin; for each, decodes it with the independent
oracle (pycrate, J2735 2020) and writes the oracle's re-encoding as a hex line, or
`ERROR <reason>`. Used by tests/oracle.rs; run with the python of ../shared/oracle/setup.sh."""
import os
import sys

shared = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "..", "..", "shared")
sys.path.insert(0, os.path.join(shared, "j2735"))
import j2735_2020 as M  # noqa: E402

MF = M.MessageFrame.MessageFrame
for line in sys.stdin:
    line = line.strip()
    if not line:
        continue
    try:
        MF.from_uper(bytes.fromhex(line))
        print(MF.to_uper().hex(), flush=True)
    except Exception as e:  # the oracle's own refusal, reported on the line
        print(f"ERROR {type(e).__name__}: {e}".replace("\n", " "), flush=True)
