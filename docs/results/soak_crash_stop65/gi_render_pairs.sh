#!/bin/bash
# Issue 30's heap corruption, reproduced faster (stop 65): hpsf and anhpsf side by side at 8×8 through
# gi-render (the soak's frame: renderModuleFrame, validation and the bounds checks on), FRAMES frames each
# (default 50,000, about 75 s a round here), ROUNDS rounds (default 20). Each round's exit codes and any
# glibc heap message go to $LOG (default /tmp/gi_render_pairs.log), each run's output to /tmp/pairs_<method>_<round>.log.
# Extra gi-render options in $EXTRA (stop 65 ran it with and without --validation); VK_ICD_FILENAMES,
# LD_PRELOAD and the rest of the environment pass through (stop 65 also ran a self-built lavapipe under
# AddressSanitizer this way).
cd "$(dirname "$0")/../../../build/tests"
log=${LOG:-/tmp/gi_render_pairs.log}
for round in $(seq 1 "${ROUNDS:-20}"); do
  for method in hpsf anhpsf; do
    ( XDG_RUNTIME_DIR=/tmp ../bin/gi-render --scene ../../assets/cornell_box/cornell_box.gltf --method $method \
        --size 8x8 --frames "${FRAMES:-50000}" --max-bounces 1 --check-bounds ${EXTRA---validation} \
        --out /tmp/pairs_$method.exr > /tmp/pairs_${method}_$round.log 2>&1
      echo "rc=$?" >> /tmp/pairs_${method}_$round.log ) &
  done
  wait
  echo "$(date +%T) round $round: $(grep -h -E 'rc=|malloc|free\(\)|corrupt|bad_alloc|ERROR: AddressSanitizer' \
    /tmp/pairs_hpsf_$round.log /tmp/pairs_anhpsf_$round.log | tr '\n' ' ')" >> "$log"
done
