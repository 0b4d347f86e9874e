#!/bin/sh
# Writes the launcher script of each control with machine cycles (fmsvm dialects --launcher NAME).
# Run from the repository's root after a catalogue changes; tests/post.rs checks they are current.
set -e
FMSVM=${FMSVM:-target/debug/fmsvm}
for control in fanuc0itd mayak600t nc31 sinumerik802d fagor8035t iso; do
    "$FMSVM" dialects --launcher "$control" > "post/fmsvm_post_$control.py"
done
