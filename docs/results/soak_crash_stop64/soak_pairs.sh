#!/bin/bash
# Issue 30's heap corruption, reproduced (stop 64): both 10,000-frame soaks side by side, as `ctest -j2`
# may run them, ROUNDS times (default 8); each round's outcome and any crash report's first line in
# /tmp/soakloop.log, the logs in /tmp/soak_{h,a}_<round>.log. Stop 64 ran 8 rounds: round 8's anhpsf soak
# aborted (anhpsf_round8.log beside this script).
cd "$(dirname "$0")/../../../build/tests"
for round in $(seq 1 "${ROUNDS:-8}"); do
  XDG_RUNTIME_DIR=/tmp ../bin/gpu_tests --gtest_filter='SoakTest.Hpsf*' > /tmp/soak_h_$round.log 2>&1 &
  XDG_RUNTIME_DIR=/tmp ../bin/gpu_tests --gtest_filter='SoakTest.Anhpsf*' > /tmp/soak_a_$round.log 2>&1
  wait
  echo "round $round: $(grep -h -E 'PASSED|FAILED  \]|bad_alloc|crash_report' /tmp/soak_h_$round.log /tmp/soak_a_$round.log | tr '\n' ' ')" >> /tmp/soakloop.log
done
