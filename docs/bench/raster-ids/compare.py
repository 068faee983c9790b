# The H100's frames before (base) and after (ids) the raster with ids, compared pixel by pixel
# (device.sh's first part writes them): pixels differing at all, by more than 8 levels, and the
# largest difference in any channel.
import sys
import numpy as np
from PIL import Image

folder = sys.argv[1] if len(sys.argv) > 1 else "."
for view in ["horizon", "oblique", "default"]:
    a = np.asarray(Image.open(f"{folder}/{view}-visibility-base.png").convert("RGB")).astype(int)
    b = np.asarray(Image.open(f"{folder}/{view}-visibility-ids.png").convert("RGB")).astype(int)
    d = np.abs(a - b).max(axis=2)
    print(f"{view}: {int((d > 0).sum())} of {d.size} pixels differ, {int((d > 8).sum())} by over 8 levels, at most {int(d.max())}")
