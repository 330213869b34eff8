"""Fit the robot's eye-socket network on rendered eye windows, and measure it on unseen people.

Usage (PyTorch, as ``pip install -e '.[rl]'`` brings it)::

    python docs/results/people/socket_net.py
        [--out src/jointattention/data/eye_socket_net.npz]
        [--table docs/results/people/socket_net.md] [--quick]

The drawn-eye bank (:mod:`jointattention.agent.eye_sockets`) places a socket several pixels
off, and a pixel is worth several degrees of the eye's turn (docs/lab-notes.md, "Reading the
eyes"). :class:`jointattention.agent.socket_net.SocketNet` is an eye-landmark network of the
robot's own: it is fitted here, once, as a face-tracking library fits its landmark model, on
windows whose true sockets the simulator knows, of caregivers of the people world drawn from a
stream no data set uses (``"socket-net"``), each window placed with an eye finder's error
(``--placement-sd`` eye distances). It never sees a held-out caregiver. It is then measured on
unseen caregivers of the held-out stream (seed 6262, which nothing else uses), beside the bank.
No gaze is taught: the network places the sockets; the learners still teach themselves where
she looks.
"""

from __future__ import annotations

import argparse
import dataclasses
import time
from pathlib import Path

import numpy as np

from jointattention._files import write_text
from jointattention.agent.eye_sockets import sockets
from jointattention.agent.socket_net import SocketNet
from jointattention.config import load_config
from jointattention.world.recording import HELD_OUT, eye_box, eye_window_at, sockets_in_window
from jointattention.world.simulator import World

ROOT = Path(__file__).parents[3]
SOCKETS = load_config(str(Path(__file__).parent / "sockets.toml")).world.eye_window
HELD_SEED, HELD_CAREGIVERS, HELD_POSES = 6262, 60, 5


def record(world, caregivers: int, poses: int, seed: int, stream: str, sd: float,
           label: str) -> tuple[np.ndarray, np.ndarray]:
    """Eye windows placed with an error of ``sd`` eye distances, and their true sockets."""
    wins, truth = [], []
    place = np.random.default_rng([seed, 0x50C7])
    start = time.perf_counter()
    for c in range(caregivers):
        with World(world, seed=seed + c, stream=stream) as w:
            for _ in range(poses):
                w.reset()
                w.set_head_angle(w.face_angle_rad)
                centre, distance = eye_box(w)
                error = place.normal(0.0, sd, 3)
                wins.append(eye_window_at(w, centre, distance, error))
                truth.append(sockets_in_window(w, centre, distance, error))
        if (c + 1) % max(1, caregivers // 10) == 0:
            print(f"  {label}: {c + 1} of {caregivers} caregivers "
                  f"({time.perf_counter() - start:.0f} s)", flush=True)
    return np.array(wins, np.uint8), np.array(truth, np.float32)


def fit(wins, truth, epochs: int, seed: int = 0) -> SocketNet:
    """The network fitted to ``truth`` (n, 2, 2) from ``wins`` (n, h, w), with PyTorch."""
    import torch
    from torch import nn

    torch.manual_seed(seed)
    torch.set_num_threads(2)
    height, width = wins.shape[1:]
    layers, channels = [], 1
    for k, (pool, dilation) in enumerate(SocketNet.LAYERS):
        out = (16, 32, 64, 64)[k]
        layers += [nn.Conv2d(channels, out, 3, padding=dilation, dilation=dilation), nn.ReLU()]
        layers += [nn.MaxPool2d(2)] if pool else []
        channels = out
    layers.append(nn.Conv2d(channels, 2, 3, padding=1))
    body = nn.Sequential(*layers)
    convs = [m for m in body if isinstance(m, nn.Conv2d)]

    def forward(x):
        heat = body(x)
        n, _, hh, ww = heat.shape
        ys = (torch.arange(hh) + 0.5) * SocketNet.POOLED - 0.5
        xs = (torch.arange(ww // 2) + 0.5) * SocketNet.POOLED - 0.5
        out = []
        for eye in range(2):
            half = heat[:, eye, :, eye * (ww // 2):(eye + 1) * (ww // 2)]
            p = half.reshape(n, -1).softmax(1).reshape(n, hh, ww // 2)
            out += [(p.sum(1) * xs).sum(1) + eye * (ww // 2) * SocketNet.POOLED,
                    (p.sum(2) * ys).sum(1)]
        return torch.stack(out, 1)

    x = torch.tensor(wins, dtype=torch.float32)[:, None] / 255.0
    x = (x - x.mean((2, 3), keepdim=True)) / (x.std((2, 3), keepdim=True) + 1e-3)
    y = torch.tensor(truth.reshape(len(truth), 4))
    batch = 64
    opt = torch.optim.Adam(body.parameters(), 2e-3)
    sched = torch.optim.lr_scheduler.OneCycleLR(opt, 2e-3,
                                                total_steps=epochs * -(-len(x) // batch))
    order = torch.Generator().manual_seed(seed)
    start = time.perf_counter()
    for epoch in range(epochs):
        for i in torch.randperm(len(x), generator=order).split(batch):
            loss = nn.functional.smooth_l1_loss(forward(x[i]), y[i])
            opt.zero_grad()
            loss.backward()
            opt.step()
            sched.step()
        print(f"  epoch {epoch + 1} of {epochs}: loss {loss.item():.3f} "
              f"({time.perf_counter() - start:.0f} s)", flush=True)
    weights = {"window_px": np.array([width, height])}
    for k, conv in enumerate(convs):
        weights[f"conv{k}_w"] = conv.weight.detach().numpy()
        weights[f"conv{k}_b"] = conv.bias.detach().numpy()
    net = SocketNet(weights)
    with torch.no_grad():  # the numpy forward pass is the network's
        gap = np.abs(net.predict(wins[:64]) - forward(x[:64]).numpy().reshape(-1, 2, 2)).max()
    if not gap < 1e-3:
        raise RuntimeError(f"the numpy forward pass is {gap:.2g} px from PyTorch's")
    return net


def errors_px(found: np.ndarray, truth: np.ndarray) -> np.ndarray:
    """Each socket's distance from the truth (px)."""
    return np.linalg.norm(found - truth, axis=-1).ravel()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--caregivers", type=int, default=3000, help="training caregivers")
    parser.add_argument("--poses", type=int, default=20, help="views of each")
    parser.add_argument("--epochs", type=int, default=6)
    parser.add_argument("--placement-sd", type=float, default=0.1,
                        help="the windows' placement error (eye distances, s.d.)")
    parser.add_argument("--out", default="src/jointattention/data/eye_socket_net.npz")
    parser.add_argument("--table", default="docs/results/people/socket_net.md")
    parser.add_argument("--quick", action="store_true", help="a few caregivers, one epoch")
    args = parser.parse_args()
    if args.quick:
        args.caregivers, args.poses, args.epochs = 8, 4, 1
    start = time.perf_counter()
    world = dataclasses.replace(load_config("people").world, eye_window=dataclasses.replace(
        SOCKETS, placement_sd=0.0, socket_patch_px=0))
    wins, truth = record(world, args.caregivers, args.poses, 0, "socket-net",
                         args.placement_sd, "training views")
    held_caregivers = 4 if args.quick else HELD_CAREGIVERS
    held, held_truth = record(world, held_caregivers, HELD_POSES, HELD_SEED, HELD_OUT,
                              args.placement_sd, "unseen caregivers")
    net = fit(wins, truth, args.epochs)
    net.command = "python docs/results/people/socket_net.py"
    net.save(args.out)
    span = world.eye_window.span
    by_bank = np.array([sockets(w, span, "bank") for w in held])
    rows = ["| finder | median error | 90th percentile | 99th percentile | s.d. across, up |",
            "|---|---|---|---|---|"]
    for name, found in (("drawn-eye bank (eye_sockets)", by_bank),
                        ("socket network (socket_net)", net.predict(held))):
        e = errors_px(found, held_truth)
        sd = (found - held_truth).reshape(-1, 2).std(axis=0)
        rows.append(f"| {name} | {np.median(e):.2f} px | {np.percentile(e, 90):.2f} px | "
                    f"{np.percentile(e, 99):.2f} px | {sd[0]:.2f}, {sd[1]:.2f} px |")
    px_per_distance = world.eye_window.width_px / world.eye_window.span
    text = "\n".join([*rows, "", (
        f"Both sockets of {held_caregivers} unseen caregivers x {HELD_POSES} poses of the people "
        f"world (held-out seed {HELD_SEED}), in {world.eye_window.width_px} x "
        f"{world.eye_window.height_px} windows ({px_per_distance:.0f} px per eye distance) "
        f"placed with an error of {args.placement_sd:g} eye distances; the network fitted on "
        f"{len(wins):,} views of {args.caregivers:,} other caregivers, {args.epochs} epochs; "
        f"`python docs/results/people/socket_net.py` "
        f"({(time.perf_counter() - start) / 60:.1f} min).")]) + "\n"
    print(write_text(args.table, text))
    print(text)


if __name__ == "__main__":
    main()
