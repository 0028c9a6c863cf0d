#!/usr/bin/env python3
"""Trains pensight's compact depth-completion network and exports it as ONNX.

    scripts/train_depth.py --data DIR --out FILE.onnx [--val DIR] [--epochs E] [--minutes M]
                           [--batch B] [--lr LR] [--threads T] [--max-steps S] [--seed S]
                           [--crop WxH] [--checkpoint FILE]

DIR is a `pensight depth-data` folder (sim/depth_training.h): depth_data.txt ("key: value"
lines), image.u8 (N*H*W grey), depth_mm.u16 (N*H*W ground-truth z-depth in mm, 0 = no net),
points.f32 (N*max_points*4: x_px, y_px, depth_m, quality), num_points.i32 (N) and wall.f32
(N*2: the net wall's curvature in 1/m, the focal length in network pixels).

The network sees the grey image, TRUDepth's prior maps S1/S2 (kernels/sparse_prior): for
every pixel the nearest sparse point after snapping to the pixel grid, S1 = its depth and
S2 = exp(-r^2 / (2 sigma^2)), and the prior surface Q (pipeline/depth/prior_surface.h: a
quadric in inverse depth fitted through the points, its curvatures pulled towards the net
wall's), and predicts a correction factor to Q.
Samples without points are skipped (the pipeline does not run the network without priors).
Without --val the last 10 % of DIR's samples are the validation set.

Writes FILE.onnx (opset 17, static 1x1xHxW "image" and 1x3xHxW "prior" in, 1x1xHxW "depth" in
metres out, BatchNorm folded into the convolutions) and FILE.onnx.json, the one-line JSON summary
that also goes to stdout. Exit code 2 on unusable input (missing or inconsistent data files, a
checkpoint that cannot be resumed).
"""
import argparse
import hashlib
import json
import math
import os
import sys
import time
import warnings

import numpy as np
import onnx
from onnx import numpy_helper
import torch
import torch.nn as nn
import torch.nn.functional as F

# torch 1.13 flags scatter_reduce as beta; its "amin" result is exact and tested here.
warnings.filterwarnings("ignore", message="scatter_reduce")

# Exported opset: the highest torch 1.13 writes, and the one pensight's exporter targets.
OPSET = 17


class InputError(Exception):
    """Unusable data or checkpoint: reported as one line and exit code 2."""


# ---------------------------------------------------------------------------------------------
# Data


def read_meta(folder):
    """depth_data.txt as a dict of the keys this script uses; other keys are ignored."""
    path = os.path.join(folder, "depth_data.txt")
    if not os.path.isfile(path):
        raise InputError(f"{path} is missing (write the folder with `pensight depth-data`)")
    raw = {}
    with open(path) as f:
        for line in f:
            key, sep, value = line.partition(":")
            if sep:
                raw[key.strip()] = value.strip()
    meta = {}
    for key, kind in (("version", int), ("samples", int), ("width", int), ("height", int),
                      ("max_points", int), ("sigma_px", float)):
        if key not in raw:
            raise InputError(f"{path}: no '{key}:' line")
        try:
            meta[key] = kind(raw[key])
        except ValueError:
            raise InputError(f"{path}: '{key}: {raw[key]}' is not a number") from None
    if meta["version"] != 2:
        raise InputError(f"{path}: version {meta['version']}, this script reads version 2 "
                         "(write the folder again with this build's `pensight depth-data`)")
    if min(meta["samples"], meta["width"], meta["height"], meta["max_points"]) < 1:
        raise InputError(f"{path}: samples, width, height and max_points must be positive")
    if not meta["sigma_px"] > 0 or not math.isfinite(meta["sigma_px"]):
        raise InputError(f"{path}: sigma_px must be positive and finite")
    return meta


def map_array(folder, name, dtype, shape, memmap):
    """The file `name` as an array of `shape`, after checking its size."""
    path = os.path.join(folder, name)
    if not os.path.isfile(path):
        raise InputError(f"{path} is missing")
    expected = int(np.prod(shape)) * np.dtype(dtype).itemsize
    actual = os.path.getsize(path)
    if actual != expected:
        raise InputError(f"{path} holds {actual} bytes, depth_data.txt implies {expected} "
                         f"({' x '.join(map(str, shape))} {np.dtype(dtype).name})")
    if memmap:
        return np.memmap(path, dtype=dtype, mode="r", shape=shape)
    return np.fromfile(path, dtype=dtype).reshape(shape)


def snap(v):
    """kernels/sparse_prior's snapping rule, floor(v + 0.5) in float32."""
    return torch.floor(v.float() + 0.5).long()


# pipeline/depth/prior_surface.h's ridge, relative to the sum of the weights: none on the
# constant, a token one on the slopes (a row of points leaves the slope across it at 0), and one
# on the curvatures that only points spread over the image overcome.
SURFACE_RIDGE = np.array([0.0, 1e-6, 1e-6, 1e-3, 1e-3, 1e-3])


def wall_curvatures(c, m_ref, half_width, curvature_per_m, focal_px):
    """pipeline/depth/prior_surface.cpp's wall_curvatures: the quadric's curvatures for a vertical
    cylinder of curvature_per_m seen along the normal of c's plane part, no camera roll (u^2
    only, prior_surface.h); zeros without a curvature or focal length, or for a plane steeper
    than 45 deg from the vertical."""
    target = np.zeros(6)
    if not curvature_per_m > 0 or not focal_px > 0:
        return target
    s = half_width / focal_px
    n = np.array([c[1] / s, c[2] / s, c[0]])
    n /= np.linalg.norm(n)
    if not n[2] > 0 or abs(n[1]) > math.sqrt(0.5):
        return target
    target[3] = m_ref * curvature_per_m * s * s / (2 * n[2] * (n[1] ** 2 + n[2] ** 2))
    return target


def fit_prior_surface(x, y, depth, quality, height, width, curvature_per_m=0.0, focal_px=0.0):
    """pipeline/depth/prior_surface.h's fit_prior_surface in float64: the quadric
    t = m_ref / z = c0 + c1 u + c2 v + c3 u^2 + c4 u v + c5 v^2 over u = (x - (W-1)/2) / (W/2),
    v = (y - (H-1)/2) / (W/2), least squares weighted by the quality (all 1 when none is
    positive) with SURFACE_RIDGE, the curvatures pulled towards the net wall's (wall_curvatures)
    when its curvature and the focal length are given. Returns (c [6], m_ref, t_min, t_max)."""
    x, y, z = (np.asarray(a, np.float64) for a in (x, y, depth))
    w = np.asarray(quality, np.float64)
    w = np.where(np.isfinite(w) & (w > 0), w, 0.0)
    if not w.sum() > 0:
        w = np.ones_like(z)
    m_ref = float((w * z).sum() / w.sum())
    half = width / 2
    u, v = (x - (width - 1) / 2) / half, (y - (height - 1) / 2) / half
    a = np.stack([np.ones_like(u), u, v, u * u, u * v, v * v], 1)
    t = m_ref / z
    ridge = SURFACE_RIDGE * w.sum()
    normal = a.T @ (w[:, None] * a) + np.diag(ridge)
    rhs = a.T @ (w * t)
    c = np.linalg.solve(normal, rhs)
    target = wall_curvatures(c, m_ref, half, curvature_per_m, focal_px)
    if target.any():
        c = np.linalg.solve(normal, rhs + ridge * target)
    return c, m_ref, float(t.min()), float(t.max())


def render_prior_surface(fit, height, width):
    """Q = m_ref / clamp(t(u, v), t_min / 2, 2 t_max) at every pixel centre, [H, W] float32."""
    c, m_ref, t_min, t_max = fit
    half = width / 2
    u = (np.arange(width, dtype=np.float64) - (width - 1) / 2)[None, :] / half
    v = (np.arange(height, dtype=np.float64) - (height - 1) / 2)[:, None] / half
    t = c[0] + c[1] * u + c[2] * v + c[3] * u * u + c[4] * u * v + c[5] * v * v
    return (m_ref / np.clip(t, t_min / 2, 2 * t_max)).astype(np.float32)


def nearest_labels(xs, ys, height, width, max_points):
    """Index of the nearest point per pixel ([H, W] int16), ties to the lowest index.

    Exact and separable: the key r^2 * max_points + index orders candidates by distance, then
    by index. Pass 1 keeps per occupied column and row the best point of that column (dy^2
    only); pass 2 adds dx^2 column by column into a running minimum over H x W.
    """
    count = xs.numel()
    index = torch.arange(count, dtype=torch.int32)
    rows = torch.arange(height, dtype=torch.int32)
    cols, col_of_point = torch.unique(xs, return_inverse=True)
    key1 = (rows[None, :] - ys[:, None].int()) ** 2 * max_points + index[:, None]  # [K, H]
    best = torch.full((cols.numel(), height), torch.iinfo(torch.int32).max, dtype=torch.int32)
    best.scatter_reduce_(0, col_of_point[:, None].expand(count, height), key1, reduce="amin")
    dx2 = (torch.arange(width, dtype=torch.int32)[None, :] - cols[:, None].int()) ** 2
    dx2 *= max_points  # [C, W]
    key = torch.full((height, width), torch.iinfo(torch.int32).max, dtype=torch.int32)
    candidate = torch.empty_like(key)
    for c in range(cols.numel()):
        torch.add(best[c, :, None], dx2[c, None, :], out=candidate)
        torch.minimum(key, candidate, out=key)
    return (key % max_points).to(torch.int16)


class DepthData:
    """One depth-data folder: images and ground truth mapped from disk, the nearest-point label
    of every pixel in RAM (2 bytes per pixel, from which S1/S2 are exact), only for the samples
    that have points."""

    def __init__(self, folder, samples=None):
        self.folder = folder
        meta = read_meta(folder)
        n, h, w, k = meta["samples"], meta["height"], meta["width"], meta["max_points"]
        if k > 32767:
            raise InputError(f"{folder}/depth_data.txt: max_points {k} exceeds int16 labels")
        self.height, self.width, self.max_points, self.sigma_px = h, w, k, meta["sigma_px"]
        self.image = map_array(folder, "image.u8", np.uint8, (n, h, w), memmap=True)
        self.depth_mm = map_array(folder, "depth_mm.u16", "<u2", (n, h, w), memmap=True)
        points = map_array(folder, "points.f32", "<f4", (n, k, 4), memmap=True)
        counts = map_array(folder, "num_points.i32", "<i4", (n,), memmap=False)
        walls = map_array(folder, "wall.f32", "<f4", (n, 2), memmap=False).astype(np.float64)
        chosen = np.arange(n) if samples is None else samples
        bad = chosen[(counts[chosen] < 0) | (counts[chosen] > k)]
        if bad.size:
            raise InputError(f"{folder}/num_points.i32: sample {bad[0]} has {counts[bad[0]]} "
                             f"points, outside 0..{k}")
        self.without_points = int((counts[chosen] == 0).sum())
        self.samples = chosen[counts[chosen] > 0]
        self.xs = torch.zeros(len(self.samples), k, dtype=torch.int32)
        self.ys = torch.zeros(len(self.samples), k, dtype=torch.int32)
        self.point_depth = torch.zeros(len(self.samples), k)
        self.labels = torch.empty(len(self.samples), h, w, dtype=torch.int16)
        self.surfaces = []
        for i, s in enumerate(self.samples):
            p = torch.from_numpy(np.array(points[s, :counts[s]]))
            x, y = snap(p[:, 0]), snap(p[:, 1])
            outside = ~torch.isfinite(p[:, :3]).all(1) | (x < 0) | (y < 0) | (x >= w) | (y >= h)
            if outside.any():
                j = int(outside.nonzero()[0])
                raise InputError(f"{folder}/points.f32: sample {s} point {j} "
                                 f"({p[j, 0]:.2f}, {p[j, 1]:.2f}, depth {p[j, 2]:.3f}) is not "
                                 f"finite or lies outside the {w}x{h} image")
            self.xs[i, :len(p)], self.ys[i, :len(p)], self.point_depth[i, :len(p)] = x, y, p[:, 2]
            self.labels[i] = nearest_labels(x, y, h, w, k)
            self.surfaces.append(fit_prior_surface(p[:, 0].numpy(), p[:, 1].numpy(),
                                                   p[:, 2].numpy(), p[:, 3].numpy(), h, w,
                                                   walls[s, 0], walls[s, 1]))
        self.u = torch.arange(w, dtype=torch.int32).view(1, 1, w)
        self.v = torch.arange(h, dtype=torch.int32).view(1, h, 1)
        # float32 like the C++ kernels, so that S2 rounds the same way.
        self.inv_two_sigma2 = 1 / (2 * torch.tensor(self.sigma_px, dtype=torch.float32) ** 2)

    def __len__(self):
        return len(self.samples)

    def batch(self, rows):
        """image [B,1,H,W] in 0..1, prior [B,3,H,W] (S1 in m, S2, Q in m), ground truth
        [B,1,H,W] in m (0 = no net) of the usable samples `rows` (indices into self.samples)."""
        rows = np.asarray(rows)
        files = self.samples[rows]
        image = torch.from_numpy(self.image[files].astype(np.float32) / 255)
        gt = torch.from_numpy(self.depth_mm[files].astype(np.float32) / 1000)
        t = torch.from_numpy(rows)
        label = self.labels[t].long().flatten(1)  # [B, H*W]
        size = (len(rows), self.height, self.width)
        s1 = self.point_depth[t].gather(1, label).view(size)
        dx = self.u - self.xs[t].gather(1, label).view(size)
        dy = self.v - self.ys[t].gather(1, label).view(size)
        s2 = torch.exp(-(dx * dx + dy * dy).float() * self.inv_two_sigma2)
        q = torch.from_numpy(np.stack([render_prior_surface(self.surfaces[r], self.height,
                                                            self.width) for r in rows]))
        return image[:, None], torch.stack([s1, s2, q], 1), gt[:, None]


def augment(image, prior, gt, rng, crop):
    """Flips, brightness/contrast, depth scale (S1, Q and ground truth together) and an optional
    random crop, drawn per sample. A flip of the points flips their surface exactly (its
    coordinates are centred and its ridge symmetric)."""
    out = []
    for i in range(image.shape[0]):
        im, pr, g = image[i], prior[i], gt[i]
        for axis in (-1, -2):
            if rng.random() < 0.5:
                im, pr, g = im.flip(axis), pr.flip(axis), g.flip(axis)
        im = (im * rng.uniform(0.6, 1.4) + rng.uniform(-0.1, 0.1)).clamp(0, 1)
        scale = math.exp(rng.uniform(math.log(0.8), math.log(1.25)))
        pr = torch.stack([pr[0] * scale, pr[1], pr[2] * scale])
        g = g * scale
        if crop:
            top = int(rng.integers(0, im.shape[-2] - crop[0] + 1))
            left = int(rng.integers(0, im.shape[-1] - crop[1] + 1))
            window = (..., slice(top, top + crop[0]), slice(left, left + crop[1]))
            im, pr, g = im[window], pr[window], g[window]
        out.append((im, pr, g))
    return tuple(torch.stack(t) for t in zip(*out))


# ---------------------------------------------------------------------------------------------
# Network


def conv_bn_relu(cin, cout, stride=1):
    return nn.Sequential(nn.Conv2d(cin, cout, 3, stride, 1, bias=False), nn.BatchNorm2d(cout),
                         nn.ReLU(inplace=True))


class CompactDepthNet(nn.Module):
    """U-Net depth completion: a correction factor to the prior surface Q, scale-equivariant
    through the per-frame prior depth m.

    m = mean(S1) + 1e-3; the encoder sees (image, S1/m, S2, Q/m); the decoder concatenates the
    encoder skip and the normalized prior (average-pooled) at /16, /8, /4 and /2; the head
    predicts the factor through a softplus at /2 (1 before training: the output starts as Q),
    upsampled to the input size and multiplied by Q. Input sizes must be multiples of 16
    (240 x 320 is). Only ops of pensight's ONNX importer are exported: channel picks are constant
    1x1 Convs and elementwise ops rather than Slices.
    """

    ENCODER = (16, 32, 64, 96, 128)  # channels at /2, /4, /8, /16, /32
    DECODER = (96, 48, 24, 16)  # channels at /16, /8, /4, /2
    PRIORS = 3  # S1, S2, Q

    def __init__(self):
        super().__init__()
        # Fixed 1x1 convolutions (OpenCV 4.6 cannot broadcast a computed [1,1,1,1] tensor against
        # a constant): (S1, S2, Q) -> S1 + 1e-3 and -> Q, and m -> the divisor (m, 1, m).
        self.register_buffer("pick_s1", torch.tensor([1.0, 0.0, 0.0]).view(1, 3, 1, 1),
                             persistent=False)
        self.register_buffer("pick_q", torch.tensor([0.0, 0.0, 1.0]).view(1, 3, 1, 1),
                             persistent=False)
        self.register_buffer("eps", torch.tensor([1e-3]), persistent=False)
        self.register_buffer("spread_w", torch.tensor([1.0, 0.0, 1.0]).view(3, 1, 1, 1),
                             persistent=False)
        self.register_buffer("spread_b", torch.tensor([0.0, 1.0, 0.0]), persistent=False)
        encoder, cin = [], 1 + self.PRIORS
        for c in self.ENCODER:
            encoder.append(nn.Sequential(conv_bn_relu(cin, c, 2), conv_bn_relu(c, c)))
            cin = c
        self.encoder = nn.ModuleList(encoder)
        decoder = []
        for skip, c in zip(self.ENCODER[-2::-1], self.DECODER):
            decoder.append(conv_bn_relu(cin + skip + self.PRIORS, c))
            cin = c
        self.decoder = nn.ModuleList(decoder)
        self.head = nn.Conv2d(cin, 1, 3, 1, 1)
        # softplus(bias) = 1: the untrained network returns the prior surface.
        nn.init.normal_(self.head.weight, std=1e-3)
        nn.init.constant_(self.head.bias, math.log(math.e - 1))

    def forward(self, image, prior):
        m = F.conv2d(F.adaptive_avg_pool2d(prior, 1), self.pick_s1, self.eps)  # [B,1,1,1]
        # The per-frame scalars are spread to the full size before dividing and multiplying:
        # OpenCV 4.6's ONNX importer takes Div and Mul of two computed tensors only when their
        # shapes are equal.
        size = prior.shape[-2:]
        m_map = F.interpolate(m, size=size, mode="nearest")
        divisor = F.conv2d(m, self.spread_w, self.spread_b)  # (m, 1, m)
        p = prior / F.interpolate(divisor, size=size, mode="nearest")
        surface = F.conv2d(p, self.pick_q)  # Q / m
        x = torch.cat([image, p], 1)
        skips = []
        for level in self.encoder:
            x = level(x)
            skips.append(x)
        priors = []
        for _ in self.decoder:
            p = F.avg_pool2d(p, 2, count_include_pad=False)  # no Pad node in the export
            priors.append(p)  # /2, /4, /8, /16
        d = skips[-1]
        for conv, skip, q in zip(self.decoder, reversed(skips[:-1]), reversed(priors)):
            # Resize to the skip's size: /32 -> /16 is 8 -> 15 rows at 240.
            d = F.interpolate(d, size=skip.shape[-2:], mode="bilinear", align_corners=False)
            d = conv(torch.cat([d, skip, q], 1))
        y = F.softplus(self.head(d))
        y = F.interpolate(y, size=image.shape[-2:], mode="bilinear", align_corners=False)
        return y * surface * m_map


def conv_gflop(model, height, width):
    """2 x multiply-adds of the convolutions for one height x width frame."""
    macs = []

    def hook(conv, _, out):
        macs.append(out.numel() * conv.in_channels // conv.groups * math.prod(conv.kernel_size))

    handles = [c.register_forward_hook(hook) for c in model.modules() if isinstance(c, nn.Conv2d)]
    was_training = model.training
    model.eval()
    with torch.no_grad():
        model(torch.zeros(1, 1, height, width), torch.ones(1, 3, height, width))
    model.train(was_training)
    for h in handles:
        h.remove()
    return 2 * sum(macs) / 1e9


# ---------------------------------------------------------------------------------------------
# Loss and metrics


def silog_rmse_loss(pred, gt):
    """SILog (AdaBins: 10 * sqrt(var(g) + 0.15 * mean(g)^2), g = log pred - log gt) plus RMSE in
    metres, over the pixels with ground truth."""
    mask = gt > 0
    if not mask.any():
        return pred.sum() * 0
    p, t = pred[mask], gt[mask]
    g = torch.log(p.clamp_min(1e-3)) - torch.log(t)
    silog = 10 * torch.sqrt(g.var(unbiased=False) + 0.15 * g.mean() ** 2 + 1e-8)
    rmse = torch.sqrt(((p - t) ** 2).mean() + 1e-8)
    return silog + rmse


class Metrics:
    """AbsRel, delta < 1.25 and RMSE of the network, and AbsRel of S1 alone and of the prior
    surface Q alone, over all pixels with ground truth."""

    def __init__(self):
        self.pixels = self.absrel = self.delta1 = self.sq = 0.0
        self.s1_absrel = self.surface_absrel = 0.0

    def add(self, pred, prior, gt):
        mask = gt[:, 0] > 0
        t = gt[:, 0][mask].double()
        p, s, q = (a[mask].double() for a in (pred[:, 0], prior[:, 0], prior[:, 2]))
        self.pixels += t.numel()
        self.absrel += float(((p - t).abs() / t).sum())
        self.delta1 += float((torch.maximum(p / t, t / p.clamp_min(1e-6)) < 1.25).sum())
        self.sq += float(((p - t) ** 2).sum())
        self.s1_absrel += float(((s - t).abs() / t).sum())
        self.surface_absrel += float(((q - t).abs() / t).sum())

    def result(self):
        n = max(self.pixels, 1)
        return {"val_absrel": self.absrel / n, "val_delta1": self.delta1 / n,
                "val_rmse_m": math.sqrt(self.sq / n), "s1_absrel": self.s1_absrel / n,
                "surface_absrel": self.surface_absrel / n}


def evaluate(model, data, batch):
    model.eval()
    metrics = Metrics()
    with torch.no_grad():
        for start in range(0, len(data), batch):
            image, prior, gt = data.batch(range(start, min(start + batch, len(data))))
            metrics.add(model(image, prior), prior, gt)
    model.train()
    return metrics.result()


# ---------------------------------------------------------------------------------------------
# Training


def learning_rate(base, progress):
    """Linear warm-up over the first 3 % of the run, then cosine decay to 1 % of `base`."""
    warm = 0.03
    if progress < warm:
        return base * max(progress / warm, 0.05)
    t = min((progress - warm) / (1 - warm), 1.0)
    return base * (0.01 + 0.99 * 0.5 * (1 + math.cos(math.pi * t)))


def parse_size(text):
    """An image size "WxH" (width first, as image sizes are written) as (height, width), both
    multiples of 16 (the network's five stride-2 levels)."""
    try:
        w, h = (int(v) for v in text.lower().split("x"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected WxH, got '{text}'") from None
    if h < 16 or w < 16 or h % 16 or w % 16:
        raise argparse.ArgumentTypeError(f"{text}: W and H must be multiples of 16")
    return h, w


def parse_args():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--data", required=True, help="depth-data folder to train on")
    ap.add_argument("--val", help="depth-data folder to validate on "
                                  "(default: the last 10 %% of --data)")
    ap.add_argument("--out", required=True, help="ONNX file to write")
    ap.add_argument("--epochs", type=int, default=40)
    ap.add_argument("--minutes", type=float, default=0,
                    help="wall-clock budget of the training, resumed runs included (0: none); "
                         "training stops cleanly when it is spent, then exports")
    ap.add_argument("--batch", type=int, default=8)
    ap.add_argument("--lr", type=float, default=1e-3)
    ap.add_argument("--threads", type=int, default=2, help="torch.set_num_threads")
    ap.add_argument("--max-steps", type=int, default=0, help="stop after this many steps (0: none)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--crop", type=parse_size, help="train on random WxH crops (multiples of 16)")
    ap.add_argument("--checkpoint", help="state saved every epoch; resumed from if it exists")
    ap.add_argument("--also-export", type=parse_size, action="append", default=[],
                    metavar="WxH", help="also write the network for WxH input (another camera "
                    "aspect, multiples of 16) as OUT with _WxH before .onnx; repeatable")
    args = ap.parse_args()
    for name in ("epochs", "batch", "threads"):
        if getattr(args, name) < 1:
            ap.error(f"--{name} must be at least 1")
    if args.max_steps < 0 or args.minutes < 0 or not args.lr > 0:
        ap.error("--max-steps and --minutes must be >= 0 and --lr positive")
    return args


def load_data(args):
    meta = read_meta(args.data)
    if args.val:
        train, val = DepthData(args.data), DepthData(args.val)
        if (val.height, val.width) != (train.height, train.width):
            raise InputError(f"{args.val}: {val.width}x{val.height} images, {args.data} has "
                             f"{train.width}x{train.height}")
    else:
        n = meta["samples"]
        if n < 2:
            raise InputError(f"{args.data}: {n} sample, at least 2 are needed without --val")
        n_val = max(1, round(0.1 * n))
        train = DepthData(args.data, np.arange(n - n_val))
        val = DepthData(args.data, np.arange(n - n_val, n))
    if args.crop and (args.crop[0] > train.height or args.crop[1] > train.width):
        raise InputError(f"--crop {args.crop[1]}x{args.crop[0]} is larger than the "
                         f"{train.width}x{train.height} images of {args.data}")
    for name, d in (("train", train), ("val", val)):
        if len(d) == 0:
            raise InputError(f"{d.folder}: no {name} sample has prior points")
    return train, val


def save_checkpoint(path, state):
    torch.save(state, path + ".tmp")
    os.replace(path + ".tmp", path)


def fold_shape_arithmetic(model):
    """Replaces Shape -> Slice -> Concat chains by constants and drops the nodes left unread.

    torch 1.13 writes each Resize's `sizes` as Concat(Shape(x)[0:2], (h, w)) even when every
    shape is static; pensight's importer (like TensorRT's static engines) wants constants.
    """
    graph = model.graph
    inferred = onnx.shape_inference.infer_shapes(model).graph
    shapes = {v.name: [d.dim_value for d in v.type.tensor_type.shape.dim]
              for v in list(inferred.value_info) + list(inferred.input)}
    consts = {i.name: numpy_helper.to_array(i) for i in graph.initializer}
    for node in graph.node:
        if node.op_type == "Constant":
            consts[node.output[0]] = numpy_helper.to_array(node.attribute[0].t)
    folded = set()
    for node in graph.node:
        args = [consts.get(name) for name in node.input]
        if node.op_type == "Shape" and all(d > 0 for d in shapes.get(node.input[0], [0])):
            value = np.array(shapes[node.input[0]], np.int64)
        elif node.op_type == "Slice" and all(a is not None for a in args):
            data, starts, ends = args[:3]
            axes = args[3] if len(args) > 3 else range(len(starts))
            steps = args[4] if len(args) > 4 else [1] * len(starts)
            window = [slice(None)] * data.ndim
            for axis, start, end, step in zip(axes, starts, ends, steps):
                window[axis] = slice(int(start), int(end), int(step))
            value = data[tuple(window)]
        elif node.op_type == "Concat" and all(a is not None for a in args):
            value = np.concatenate(args, axis=node.attribute[0].i)
        else:
            continue
        consts[node.output[0]] = value
        folded.add(node.output[0])
    used = set()
    for node in graph.node:
        if node.output[0] in folded:
            continue
        for i, name in enumerate(node.input):
            if name in folded:
                node.input[i] = name + "_folded"
                used.add(name)
    # Sorted: the file's bytes (and sha256) do not depend on Python's string hashing.
    graph.initializer.extend(numpy_helper.from_array(consts[n], n + "_folded")
                             for n in sorted(used))
    while True:
        read = {name for node in graph.node for name in node.input}
        read |= {o.name for o in graph.output}
        dead = [node for node in graph.node if not read.intersection(node.output)]
        if not dead:
            break
        for node in dead:
            graph.node.remove(node)


def export_onnx(model, height, width, path):
    """Static-shape fp32 export; written next to `path` and renamed into place."""
    model.eval()
    inputs = (torch.rand(1, 1, height, width), torch.rand(1, 3, height, width) * 4)
    tmp = path + ".tmp"
    with torch.no_grad(), warnings.catch_warnings():
        # torch 1.13's Resize symbolic warns about its own constants; the sizes are folded below.
        warnings.filterwarnings("ignore", message="The shape inference of prim::Constant")
        torch.onnx.export(model, inputs, tmp, input_names=["image", "prior"],
                          output_names=["depth"], opset_version=OPSET, do_constant_folding=True,
                          training=torch.onnx.TrainingMode.EVAL)
    exported = onnx.load(tmp)
    fold_shape_arithmetic(exported)
    left = {n.op_type for n in exported.graph.node} & {"Shape", "Slice", "Gather", "Pad"}
    if left:
        raise RuntimeError(f"export left run-time shape ops {sorted(left)} in {tmp}")
    onnx.checker.check_model(exported)
    onnx.save(exported, tmp)
    os.replace(tmp, path)
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def train(args):
    torch.manual_seed(args.seed)
    rng = np.random.default_rng(args.seed)
    t_load = time.monotonic()
    # One thread for the prior maps: their per-column ops are too small to gain from more.
    torch.set_num_threads(1)
    train_data, val_data = load_data(args)
    torch.set_num_threads(args.threads)
    print(f"data: {len(train_data)} train, {len(val_data)} val samples at "
          f"{train_data.width}x{train_data.height}; skipped without prior points: "
          f"{train_data.without_points} train, {val_data.without_points} val; priors built in "
          f"{time.monotonic() - t_load:.1f} s", flush=True)

    model = CompactDepthNet()
    gflop = conv_gflop(model, train_data.height, train_data.width)
    params = sum(p.numel() for p in model.parameters())
    print(f"CompactDepthNet: {gflop:.3f} GFLOP at {train_data.width}x{train_data.height}, "
          f"{params} parameters", flush=True)
    # Weight decay on convolution kernels only, not on BatchNorm scales or biases.
    decay = [p for p in model.parameters() if p.ndim > 1]
    no_decay = [p for p in model.parameters() if p.ndim <= 1]
    optimizer = torch.optim.AdamW([{"params": decay, "weight_decay": 1e-2},
                                   {"params": no_decay, "weight_decay": 0.0}], lr=args.lr)

    epoch = step = 0
    spent_s = 0.0  # training time of earlier runs of this checkpoint
    if args.checkpoint and os.path.exists(args.checkpoint):
        try:
            state = torch.load(args.checkpoint)
            model.load_state_dict(state["model"])
            optimizer.load_state_dict(state["optimizer"])
            epoch, step, spent_s = state["epoch"], state["step"], state["spent_s"]
            rng.bit_generator.state = state["rng"]
        except Exception as e:  # unreadable, truncated or from another architecture
            why = " ".join(str(e).split())[:160]
            raise InputError(f"{args.checkpoint} cannot be resumed from ({why}); remove it to "
                             "start over") from None
        print(f"resumed {args.checkpoint}: epoch {epoch}, step {step}, {spent_s / 60:.1f} min",
              flush=True)

    def checkpoint():
        if args.checkpoint:
            save_checkpoint(args.checkpoint, {
                "model": model.state_dict(), "optimizer": optimizer.state_dict(), "epoch": epoch,
                "step": step, "spent_s": spent_s + time.monotonic() - t_start,
                "rng": rng.bit_generator.state})

    steps_per_epoch = max(1, len(train_data) // args.batch)
    total_steps = args.epochs * steps_per_epoch
    if args.max_steps:
        total_steps = min(total_steps, args.max_steps)
    budget_s = args.minutes * 60

    def progress():
        share = step / total_steps
        if budget_s:
            share = max(share, (spent_s + time.monotonic() - t_start) / budget_s)
        return share

    t_start = time.monotonic()
    model.train()
    metrics, evaluated_at = None, None
    while epoch < args.epochs and progress() < 1:
        t_epoch, losses, step_s = time.monotonic(), [], []
        order = rng.permutation(len(train_data))
        for b in range(steps_per_epoch):
            if progress() >= 1:
                break
            t_step = time.monotonic()
            for group in optimizer.param_groups:
                group["lr"] = learning_rate(args.lr, progress())
            rows = np.sort(order[b * args.batch:(b + 1) * args.batch])
            image, prior, gt = augment(*train_data.batch(rows), rng, args.crop)
            loss = silog_rmse_loss(model(image, prior), gt)
            optimizer.zero_grad(set_to_none=True)
            loss.backward()
            optimizer.step()
            step += 1
            losses.append(float(loss))
            step_s.append(time.monotonic() - t_step)
        if len(losses) == steps_per_epoch:
            epoch += 1
            label = f"epoch {epoch}"
        else:
            label = f"epoch {epoch + 1} (stopped after {len(losses)} of {steps_per_epoch} steps)"
        metrics, evaluated_at = evaluate(model, val_data, args.batch), step
        checkpoint()
        print(f"{label}, step {step}: train loss {np.mean(losses) if losses else math.nan:.4f} | "
              f"val AbsRel {metrics['val_absrel']:.4f} delta1 {metrics['val_delta1']:.4f} "
              f"RMSE {metrics['val_rmse_m']:.4f} m | S1 AbsRel {metrics['s1_absrel']:.4f} "
              f"Q AbsRel {metrics['surface_absrel']:.4f} | "
              f"{time.monotonic() - t_epoch:.1f} s, "
              f"{np.mean(step_s) if step_s else math.nan:.3f} s/step", flush=True)
    if evaluated_at != step:
        metrics = evaluate(model, val_data, args.batch)
    minutes = (spent_s + time.monotonic() - t_start) / 60

    sha256 = export_onnx(model, train_data.height, train_data.width, args.out)
    # The network is fully convolutional and scale-normalised: the same weights serve other
    # resolutions (a 16:9 camera needs a 16:9 input).
    also = {}
    for height, width in args.also_export:
        stem = args.out[:-len(".onnx")] if args.out.endswith(".onnx") else args.out
        path = f"{stem}_{width}x{height}.onnx"
        also[os.path.basename(path)] = export_onnx(model, height, width, path)
    summary = {key: round(value, 6) for key, value in metrics.items()}
    summary.update({"epochs": round(step / steps_per_epoch, 2), "steps": step,
                    "minutes": round(minutes, 2), "gflop": round(gflop, 4), "params": params,
                    "sha256": sha256, "also_exported": also})
    line = json.dumps(summary)
    with open(args.out + ".json.tmp", "w") as f:
        f.write(line + "\n")
    os.replace(args.out + ".json.tmp", args.out + ".json")
    print(line, flush=True)


def main():
    args = parse_args()
    try:
        train(args)
    except InputError as e:
        print(f"train_depth: {e}", file=sys.stderr)
        sys.exit(2)
    except KeyboardInterrupt:
        where = f"; rerun to resume from {args.checkpoint}" if args.checkpoint else ""
        print(f"train_depth: interrupted{where}", file=sys.stderr)
        sys.exit(130)


if __name__ == "__main__":
    main()
