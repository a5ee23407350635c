"""Long-running use holds no more memory than its first frames did: the process's resident
set (VmRSS) stays within a small bound after a warm-up, and the device's allocations
(``Device.memory()``) return to the same level."""

import gc

import numpy as np
import pytest

import tessera

# Resident growth allowed after a warm-up. Measured on lavapipe with the validation layer
# on: at most about 1 MiB over the loops below (the layer's and the driver's bookkeeping
# settling). Leaking one image a frame (FRAME_SIZE: 64 KiB) over 100 frames, or one volume a
# round (VOLUME_SIDE: 432 KiB) over 20 rounds, would exceed it; device memory is checked
# exactly, through the allocator's bookkeeping.
RSS_BOUND_KIB = 4096
FRAME_SIZE = (128, 128)
SIZE = (48, 48)
VOLUME_SIDE = 48


def rss_kib():
    with open("/proc/self/status") as status:
        for line in status:
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    pytest.skip("no VmRSS in /proc/self/status")


def allocations(device):
    memory = device.memory()
    return memory["allocated_bytes"], memory["allocations"]


def ball(n=20):
    x, y, z = np.meshgrid(*(np.arange(n, dtype=np.float32),) * 3, indexing="ij")
    c = (n - 1) / 2
    return np.sqrt((x - c) ** 2 + (y - c) ** 2 + (z - c) ** 2)


ISOVALUES = (3.0, 5.0, 7.0, 8.5)


def test_memory_report_counts_what_lives(device):
    gc.collect()
    before = device.memory()
    assert set(before) == {"allocated_bytes", "allocations", "reserved_bytes", "blocks"}
    r = tessera.Renderer(device, "direct")
    r.set_data(tessera.Volume(ball()))
    r.render(size=SIZE, iso=5.0)
    during = device.memory()
    assert during["allocated_bytes"] > before["allocated_bytes"]
    assert during["reserved_bytes"] >= during["allocated_bytes"]
    del r
    gc.collect()
    assert allocations(device) == (before["allocated_bytes"], before["allocations"])


@pytest.mark.parametrize("technique", ["direct", "raymarch"])
def test_a_hundred_frames_hold_no_more_memory(device, technique):
    r = tessera.Renderer(device, technique)
    r.set_data(tessera.Volume(ball()))
    # Warm-up: every isovalue once, so buffers sized by the surface have reached their size.
    for camera, iso in enumerate(ISOVALUES * 2):
        r.render(camera=(camera, 20), size=FRAME_SIZE, iso=iso)
    gc.collect()
    rss, gpu = rss_kib(), allocations(device)
    for frame in range(100):
        image = r.render(camera=(frame * 3.6, 20), size=FRAME_SIZE, iso=ISOVALUES[frame % 4])
    assert image.shape == (FRAME_SIZE[1], FRAME_SIZE[0], 4)
    gc.collect()
    assert allocations(device) == gpu
    assert rss_kib() - rss < RSS_BOUND_KIB, f"grew by {rss_kib() - rss} KiB"


def test_renderers_and_data_made_and_dropped_give_memory_back(device):
    points = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], np.float32)

    def one_round(i):
        volume = tessera.Volume(ball(VOLUME_SIDE) * (8.0 / VOLUME_SIDE) + i * 0.01)
        mesh = tessera.TetMesh(points, [[0, 1, 2, 3]], point_data=np.arange(4.0) + i)
        for technique, data in (("direct", volume), ("raymarch", volume), ("interval", mesh)):
            r = tessera.Renderer(device, technique)
            r.set_data(data)
            r.render(size=SIZE, iso=ISOVALUES[i % 4])
        # The last renderer, the volume and the mesh go here.

    # The driver's and the layer's caches fill over the first rounds.
    for i in range(8):
        one_round(i)
    gc.collect()
    rss, gpu = rss_kib(), allocations(device)
    for i in range(20):
        one_round(i)
    gc.collect()
    assert allocations(device) == gpu
    assert rss_kib() - rss < RSS_BOUND_KIB, f"grew by {rss_kib() - rss} KiB"
