"""Saving the examples' images, and showing them inline when run in a notebook."""

import numpy as np


def save(image, path):
    """Writes an (H, W, 4) uint8 image as PNG (with imageio or Pillow, whichever is there) and
    shows it inline under IPython."""
    try:
        import imageio.v3 as iio

        iio.imwrite(path, image)
    except ImportError:
        from PIL import Image

        Image.fromarray(np.asarray(image)).save(path)
    try:
        from IPython import get_ipython
        from IPython.display import Image as Shown, display

        if get_ipython() is not None:
            display(Shown(filename=str(path)))
    except ImportError:
        pass
    print(f"wrote {path}")
