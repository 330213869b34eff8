"""A small convolutional network that finds both eye sockets in an eye window.

The drawn-eye bank of :mod:`.eye_sockets` places a socket several pixels off in a 128 x 48
window: the iris, large and dark, pulls it, and the face model has no lids or eye corners to
hold it (docs/results/people/socket_net.md). This network, fitted once on rendered windows
whose true sockets the simulator knows (``python docs/results/people/socket_net.py``;
caregivers of a stream no data set uses), reads the whole window as the eye-landmark model of
a face-tracking library does. It is the robot's own part: it reads only the robot's window, as
BlazeFace reads its frame, and it is taught no gaze.

The layers: 3 x 3 convolutions with ReLU (two followed by 2 x 2 max pooling, the fourth
dilated by 2), then a convolution to one heat map per eye at a quarter of the window's
resolution; each eye's place is its map's softmax-weighted mean over its half of the window
(a soft argmax), so that it is sub-pixel and moves with the window. The forward pass is
numpy's; the weights and the window size they were fitted for are in the shipped
``eye_socket_net.npz``.

Layer 2 (the robot's parts): imports only the plumbing.
"""

from __future__ import annotations

from functools import lru_cache
from pathlib import Path

import numpy as np

from ..errors import ArgumentError, FileError

__all__ = ["NET_FILE", "SocketNet", "shipped"]

NET_FILE = "eye_socket_net.npz"


def _conv(x: np.ndarray, w: np.ndarray, b: np.ndarray, dilation: int) -> np.ndarray:
    """A 3 x 3 convolution of ``x`` (n, c, h, w), zero-padded to keep its size."""
    n, _, h, wd = x.shape
    d = dilation
    padded = np.pad(x, ((0, 0), (0, 0), (d, d), (d, d)))
    out = np.empty((w.shape[0], n, h, wd), np.float32)
    out[:] = b[:, None, None, None]
    for i in range(3):
        for j in range(3):
            part = padded[:, :, i * d:i * d + h, j * d:j * d + wd]
            out += np.tensordot(w[:, :, i, j], part, axes=(1, 1))
    return out.transpose(1, 0, 2, 3)


def _pool(x: np.ndarray) -> np.ndarray:
    """2 x 2 max pooling (odd edges dropped)."""
    h, w = x.shape[2] // 2 * 2, x.shape[3] // 2 * 2
    # four strided maxima: numpy's max over two inner axes of a reshape is many times slower
    return np.maximum(np.maximum(x[:, :, 0:h:2, 0:w:2], x[:, :, 0:h:2, 1:w:2]),
                      np.maximum(x[:, :, 1:h:2, 0:w:2], x[:, :, 1:h:2, 1:w:2]))


class SocketNet:
    """The fitted network: :meth:`predict` places both sockets in eye windows.

    ``weights``: name -> array, as the training script writes them: ``conv0_w`` ...
    ``conv4_b``, ``window_px`` (the windows' width and height fitted for) and ``command`` (the
    command that fitted it).
    """

    # (pool after, dilation) of each convolution but the last (the heat maps)
    LAYERS = ((True, 1), (True, 1), (False, 1), (False, 2))
    # how many window pixels wide a heat map's pixel is
    POOLED = 2 ** sum(pool for pool, _ in LAYERS)

    def __init__(self, weights: dict[str, np.ndarray]):
        self.weights_ = {k: np.asarray(v, np.float32) for k, v in weights.items()
                         if k.startswith("conv")}
        self.window_px = tuple(int(v) for v in np.asarray(weights["window_px"]))
        self.command = str(weights.get("command", ""))

    @classmethod
    def load(cls, path: str | Path) -> SocketNet:
        """The network saved at ``path``."""
        try:
            with np.load(path) as f:
                return cls({k: f[k] for k in f.files})
        except (OSError, KeyError, ValueError) as err:
            raise FileError(f"{path}: not an eye-socket network ({err})") from None

    def save(self, path: str | Path) -> None:
        """Write the weights to ``path`` (npz)."""
        np.savez(path, **self.weights_, window_px=np.array(self.window_px),
                 command=np.array(self.command))

    def predict(self, windows: np.ndarray, batch: int = 256) -> np.ndarray:
        """Both sockets (n, 2 eyes, x y) in window pixels, left eye first, of (n, h, w) windows."""
        windows = np.asarray(windows)
        if windows.ndim != 3 or (windows.shape[2], windows.shape[1]) != self.window_px:
            raise ArgumentError(
                f"eye windows of shape {windows.shape}: expected (n, {self.window_px[1]}, "
                f"{self.window_px[0]}), the windows the socket network was fitted on")
        return np.concatenate([self._forward(windows[i:i + batch])
                               for i in range(0, len(windows), batch)])

    def _forward(self, windows: np.ndarray) -> np.ndarray:
        x = windows.astype(np.float32)[:, None] / 255.0
        mean = x.mean(axis=(2, 3), keepdims=True)
        x = (x - mean) / (x.std(axis=(2, 3), keepdims=True) + 1e-3)
        p = self.weights_
        for k, (pool, dilation) in enumerate(self.LAYERS):
            x = np.maximum(_conv(x, p[f"conv{k}_w"], p[f"conv{k}_b"], dilation), 0.0)
            if pool:
                x = _pool(x)
        k = len(self.LAYERS)
        heat = _conv(x, p[f"conv{k}_w"], p[f"conv{k}_b"], 1)  # (n, 2, h/4, w/4)
        n, _, hh, ww = heat.shape
        ys = (np.arange(hh) + 0.5) * self.POOLED - 0.5
        xs = (np.arange(ww // 2) + 0.5) * self.POOLED - 0.5
        out = np.empty((n, 2, 2))
        for eye in range(2):  # each eye's map over its own half of the window
            half = heat[:, eye, :, eye * (ww // 2):(eye + 1) * (ww // 2)].astype(np.float64)
            e = np.exp(half - half.max(axis=(1, 2), keepdims=True))
            e /= e.sum(axis=(1, 2), keepdims=True)
            out[:, eye, 0] = (e.sum(axis=1) * xs).sum(axis=1) + eye * (ww // 2) * self.POOLED
            out[:, eye, 1] = (e.sum(axis=2) * ys).sum(axis=1)
        return out


@lru_cache(maxsize=1)
def shipped() -> SocketNet:
    """The network shipped with the package (its SHA-256 checked)."""
    from .._readers import shipped_path

    return SocketNet.load(shipped_path(NET_FILE))
