#!/usr/bin/env bash
# Rebuild the showcase in videos/showcase/ (run from the repository root after the README's
# setup command). Each command makes one video; sizes are kept to a few MB.
set -euo pipefail
out=videos/showcase
mkdir -p "$out"
sm=${SWARMSIM:-.venv/bin/swarmsim}
# GGC on the letter K: 603 robots in 3 groups (one formation each), d_cover 6, coloured by
# group; a frame every 60 ticks, 480 px wide, 30 fps.
"$sm" run K --groups 3 --seed 1 --video "$out/K-ggc-3groups.mp4" --frame-every 60 --fps 30 \
  --width 480 --color-by group --snapshot "$out/K-ggc-3groups.png" --out "$out/K-ggc-3groups" \
  --quiet
# GGC on the large K (the paper's Fig. 16): 2,000 robots in 10 groups; a frame every 80 ticks,
# 640 px wide, 30 fps (about 20 minutes).
"$sm" run K-large --seed 0 --video "$out/K-large-ggc-10groups.mp4" --frame-every 80 --fps 30 \
  --width 640 --color-by group --snapshot "$out/K-large-ggc-10groups.png" \
  --out "$out/K-large-ggc-10groups" --quiet
# keep the showcase small: summary + coverage plot only
rm -f "$out"/*/timeseries.csv "$out"/*/robots.csv "$out"/*/coverage.npz
