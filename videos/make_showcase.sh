#!/usr/bin/env bash
# Rebuild the showcase videos in videos/showcase/ (run from the repository root, after the
# README's setup command). Each line is one video; sizes are kept to a few MB.
set -euo pipefail
out=videos/showcase
mkdir -p "$out"
sm=${SWARMSIM:-.venv/bin/swarmsim}
# GGC, one group, covering the letter K (603 robots, d_cover 6), coloured by gradient.
"$sm" run K --groups 1 --seed 1 --video "$out/K-ggc-1group.mp4" --frame-every 60 --fps 30 \
  --width 480 --snapshot "$out/K-ggc-1group.png" --quiet
