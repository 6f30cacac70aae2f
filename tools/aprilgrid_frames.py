#!/usr/bin/env python3
"""The aprilgrid-frames study (docs/aprilgrid_frames.md): our corners vs OpenCV aruco's, and
which tag spacing fits the frames.

Usage: tools/aprilgrid_frames.py OUR_CORNERS.csv DATA_DIR/aprilgrid-frames
OUR_CORNERS.csv is `calibench detect --images DIR --target T.yaml --out ...` (6x6 tag36h11,
blackTagBorder 2). Needs numpy and OpenCV's Python bindings with aruco (python3-opencv).

1. OpenCV aruco (DICT_APRILTAG_36h11, markerBorderBits = 2, CORNER_REFINE_SUBPIX) on the same
   8-bit frames (16-bit frames scaled like calibench: 0.1 / 99.9 percentiles -> 0 / 255). Both
   put pixel centres at integers (calibench converts AprilTag's +0.5 convention once), so corners
   are compared as they are; aruco's corner order (marker top-left, clockwise) is matched to ours
   by the permutation of least distance per tag, reported.
2. Spacing: corner (tag r, c; k) of a grid with pitch/size rho is (c rho + dx_k, r rho + dy_k).
   EuRoC: undistort with the published cam0 radtan calibration, fit a plane homography (DLT +
   Gauss-Newton on the image residual) for each rho, report the RMS residual (px, in the
   distorted image's scale via fu). Convention "inner": the corners are taken as those of the
   1-bit inner square (each corner moved 1/10 of the tag inward). All frames: the cross ratio of
   the four corners along a tag row pair, x = 0, 1, rho, rho + 1 (rho^2 = CR / (CR - 1)), which
   needs no calibration (projective invariant; fisheye distortion over two tags biases it a bit).
"""
import csv
import sys
from collections import defaultdict

import cv2
import numpy as np

EUROC_K = np.array([[458.654, 0, 367.215], [0, 457.296, 248.375], [0, 0, 1]])
EUROC_D = np.array([-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05])
CORNER_XY = [(0, 0), (1, 0), (1, 1), (0, 1)]  # bl, br, tr, tl in tag units (board y up).


def read_gray8(path):
    im = cv2.imread(path, cv2.IMREAD_GRAYSCALE | cv2.IMREAD_ANYDEPTH)
    if im.dtype == np.uint16:
        hist = np.bincount(im.ravel(), minlength=65536).cumsum()
        lo = int(np.searchsorted(hist, 0.001 * im.size))
        hi = max(lo + 1, int(np.searchsorted(hist, 0.999 * im.size)))
        im = np.clip(np.round((im.astype(np.float64) - lo) * 255.0 / (hi - lo)), 0, 255)
        im = im.astype(np.uint8)
    return im


def aruco_corners(im):
    dictionary = cv2.aruco.getPredefinedDictionary(cv2.aruco.DICT_APRILTAG_36h11)
    params = cv2.aruco.DetectorParameters_create()
    params.markerBorderBits = 2
    params.cornerRefinementMethod = cv2.aruco.CORNER_REFINE_SUBPIX
    corners, ids, _ = cv2.aruco.detectMarkers(im, dictionary, parameters=params)
    out = {}
    if ids is not None:
        for c, i in zip(corners, ids.ravel()):
            out[int(i)] = c.reshape(4, 2).astype(np.float64)
    return out


def fit_homography_rms(board, pixels, iters=10):
    h, _ = cv2.findHomography(board, pixels, 0)
    p = h.ravel()[:8] / h[2, 2]

    def residual(p):
        hm = np.append(p, 1).reshape(3, 3)
        q = np.c_[board, np.ones(len(board))] @ hm.T
        return (q[:, :2] / q[:, 2:3] - pixels).ravel()

    for _ in range(iters):
        r = residual(p)
        jac = np.empty((len(r), 8))
        for j in range(8):
            d = np.zeros(8)
            d[j] = 1e-7 * max(1.0, abs(p[j]))
            jac[:, j] = (residual(p + d) - r) / d[j]
        p = p - np.linalg.lstsq(jac, r, rcond=None)[0]
    r = residual(p).reshape(-1, 2)
    return float(np.sqrt((r ** 2).sum(axis=1).mean()))


def board_points(tag_ids, rho, inner, cols=6):
    pts = []
    for tag, k in tag_ids:
        r, c = divmod(tag, cols)
        dx, dy = CORNER_XY[k]
        if inner:  # The 1-bit inner square: 0.1 of the tag in from each side.
            dx, dy = 0.1 + 0.8 * dx, 0.1 + 0.8 * dy
        pts.append((c * rho + dx, r * rho + dy))
    return np.array(pts, dtype=np.float64)


def cross_ratio_rhos(corners, cols=6):
    """rho from the cross ratio of the 4 corners along the bottom (k 0, 1) and top (k 3, 2)
    edges of horizontally and vertically adjacent tag pairs."""
    rhos = []
    for tag in corners:
        r, c = divmod(tag, cols)
        for other, edges in ((tag + 1, ((0, 1), (3, 2))), (tag + cols, ((0, 3), (1, 2)))):
            if other not in corners or (other == tag + 1 and c == cols - 1):
                continue
            for a, b in edges:
                x = [corners[tag][a], corners[tag][b], corners[other][a], corners[other][b]]
                d = lambda i, j: np.linalg.norm(x[i] - x[j])
                cr = d(2, 0) * d(3, 1) / (d(2, 1) * d(3, 0))
                if cr > 1:
                    rhos.append(np.sqrt(cr / (cr - 1)))
    return rhos


def main():
    ours_csv, folder = sys.argv[1], sys.argv[2]
    ours = defaultdict(lambda: defaultdict(dict))
    with open(ours_csv) as f:
        for row in csv.DictReader(f):
            ours[row["image"]][int(row["tag_id"])][int(row["corner"])] = np.array(
                [float(row["u_px"]), float(row["v_px"])])
    print("| frame | ours: tags | aruco: tags | common | median / p95 / max distance (px) | "
          "mean ours - aruco (px) | mean outward (px) | aruco order (ours k -> aruco) |")
    print("|---|---|---|---|---|---|---|---|")
    aruco_euroc = {}
    for name in sorted(ours.keys() | {"EuRoC.png", "TUM_VI.png", "r45.png", "right.png",
                                      "top.png", "top_right.png", "iphone.png",
                                      "two_boards.png"}):
        im = read_gray8(f"{folder}/{name}")
        theirs = aruco_corners(im)
        mine = {t: c for t, c in ours[name].items() if len(c) == 4}
        dists, perms, deltas, outward = [], defaultdict(int), [], []
        for tag, c in mine.items():
            if tag not in theirs:
                continue
            a = theirs[tag]
            best = min(range(4), key=lambda s: sum(
                np.linalg.norm(c[k] - a[(s - k) % 4]) for k in range(4)))
            perms[best] += 1
            dists += [np.linalg.norm(c[k] - a[(best - k) % 4]) for k in range(4)]
            centre = sum(c.values()) / 4
            for k in range(4):
                delta = c[k] - a[(best - k) % 4]
                deltas.append(delta)
                radial = (c[k] - centre) / np.linalg.norm(c[k] - centre)
                outward.append(float(delta @ radial))
            if name == "EuRoC.png":
                aruco_euroc[tag] = {k: a[(best - k) % 4] for k in range(4)}
        d = np.array(dists) if dists else np.array([np.nan])
        mean = np.mean(deltas, axis=0) if deltas else [np.nan, np.nan]
        order = ", ".join(f"aruco[(s - k) mod 4], s = {s}: {n} tags" for s, n in perms.items())
        print(f"| {name} | {len(mine)} | {len(theirs)} | {len(set(mine) & set(theirs))} | "
              f"{np.median(d):.3f} / {np.percentile(d, 95):.3f} / {d.max():.3f} | "
              f"({mean[0]:+.3f}, {mean[1]:+.3f}) | {np.mean(outward) if outward else np.nan:+.3f} | "
              f"{order} |")

    print("\nEuRoC.png, undistorted (published cam0 radtan), homography RMS (px) vs pitch/size:")
    e = ours["EuRoC.png"]
    keys = [(t, k) for t in sorted(e) for k in sorted(e[t])]
    pix = np.array([e[t][k] for t, k in keys])
    und = cv2.undistortPoints(pix.reshape(-1, 1, 2), EUROC_K, EUROC_D).reshape(-1, 2)
    und_px = und * [EUROC_K[0, 0], EUROC_K[1, 1]]  # Normalised -> pixels of focal length f.
    print("| pitch/size | outer corners | inner (1-bit) corners | distorted, outer |")
    print("|---|---|---|---|")
    best = {}
    for rho in np.round(np.arange(1.20, 1.601, 0.02), 3):
        row = []
        for inner, pts in ((False, und_px), (True, und_px), (False, pix)):
            rms = fit_homography_rms(board_points(keys, rho, inner), pts)
            row.append(rms)
        for j, rms in enumerate(row):
            if j not in best or rms < best[j][1]:
                best[j] = (rho, rms)
        print(f"| {rho:.2f} | {row[0]:.3f} | {row[1]:.3f} | {row[2]:.3f} |")
    fine = [(rho, fit_homography_rms(board_points(keys, rho, False), und_px))
            for rho in np.arange(1.25, 1.351, 0.002)]
    rho_best, rms_best = min(fine, key=lambda x: x[1])
    print(f"best (step 0.002), outer corners: pitch/size {rho_best:.3f}, RMS {rms_best:.3f} px; "
          f"best per column: {best}")

    print("\nEuRoC.png, the tags both detectors find, undistorted, pitch/size 1.30 and best:")
    common = sorted(set(aruco_euroc) & set(e))
    keys_c = [(t, k) for t in common for k in range(4)]
    for label, source in (("ours", e), ("aruco", aruco_euroc)):
        pts = np.array([source[t][k] for t, k in keys_c])
        und = cv2.undistortPoints(pts.reshape(-1, 1, 2), EUROC_K, EUROC_D).reshape(-1, 2)
        und = und * [EUROC_K[0, 0], EUROC_K[1, 1]]
        fits = [(rho, fit_homography_rms(board_points(keys_c, rho, False), und))
                for rho in np.arange(1.26, 1.361, 0.002)]
        rho_b, rms_b = min(fits, key=lambda x: x[1])
        rms_13 = fit_homography_rms(board_points(keys_c, 1.3, False), und)
        print(f"  {label}: {len(common)} tags, RMS {rms_13:.3f} px at 1.30, best {rms_b:.3f} px "
              f"at {rho_b:.3f}")

    print("\nCross-ratio pitch/size (no calibration) per frame: median [p25, p75] (n):")
    for name in sorted(ours):
        mine = {t: c for t, c in ours[name].items() if len(c) == 4}
        rhos = cross_ratio_rhos(mine)
        if rhos:
            q = np.percentile(rhos, [25, 50, 75])
            print(f"  {name}: {q[1]:.3f} [{q[0]:.3f}, {q[2]:.3f}] ({len(rhos)})")


if __name__ == "__main__":
    main()
