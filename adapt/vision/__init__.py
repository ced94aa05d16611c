"""Vision: the Match-Mediated Difference (MMD) and camera synchronisation.

Arrays in, frozen result records out; no rules, no physics, no files except
:func:`~adapt.vision.images.read_image` / :func:`~adapt.vision.images.write_image`.
Every function takes ``real`` before ``synthetic`` and never modifies its inputs.

Modules
-------
images             validation of images, the one conversion of a pair (conform), image files
scale              pixel parameters relative to 640x480; the bounded working resolution
matching           synthetic -> real corner matches (GFTT + LK, SIFT re-acquisition)
homography         H_e with USAC_MAGSAC / RANSAC, or an explicit "no alignment"
mask               the MMD mask I_m (exact and fast sum of Gaussians)
mmd                the MMD image I_d and MMDResult
regions            difference regions, expected / unexpected
texture            where the frame is flat over a textured background (camouflage)
camera_correction  eq. 3 as a fractional rotation; full pose from the floor's homography
registration       the structure's registration (a flat look, ECC) and the flat look itself
edges              edge agreement: the image's gradient on a label image's seams
edge_pose          the camera's pose (turn and shift) fitted to the image's edges at 3D seams
stillness          the frame history: which pixels held still, their median
sync               the iterative camera loop against a render callback
threads            OpenCV's thread count

Threads: adapt never changes OpenCV's thread pool on import.  The command line
and ``bench/mmd.py`` call :func:`~adapt.vision.threads.set_threads` with 2
(measured faster than 1 at 640x480 on a 2-core machine); libraries embedding
adapt decide for themselves.
"""

from __future__ import annotations
