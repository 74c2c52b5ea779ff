"""Open3D 0.16's TSDF fusion on the frames and poses of a trajectory.conf (as fine2coarse
register writes it), for bench/fusion_bench.sh: ScalableTSDFVolume (legacy) and
VoxelBlockGrid (tensor, CPU), images read included, then the mesh.

  python3 bench/fusion_open3d.py TRAJECTORY.conf DEPTH_SCALE VOXEL_SIZE {legacy,tensor} OUT.ply

Prints one JSON line: frames, seconds integrating (images read included), seconds for the
mesh, vertices, triangles, peak resident memory (bytes).
"""
import json
import resource
import sys
import time

import numpy as np
import open3d as o3d


def read_conf(path):
    scans, fx = [], None
    dirs = {}
    with open(path) as f:
        for line in f:
            w = line.split()
            if not w:
                continue
            if w[0] == "intrinsics_matrix":
                k = [float(x) for x in w[1:10]]
                fx, cx, fy, cy = k[0], k[2], k[4], k[5]
            elif w[0] in ("depth_directory", "image_directory"):
                dirs[w[0]] = line.split(None, 1)[1].strip()
            elif w[0] == "scan":
                pose = np.array([float(x) for x in w[3:19]]).reshape(4, 4)
                scans.append((dirs["depth_directory"] + "/" + w[1], dirs["image_directory"] + "/" + w[2], pose))
    return (fx, fy, cx, cy), scans


def main():
    conf, depth_scale, voxel, kind, out = sys.argv[1], float(sys.argv[2]), float(sys.argv[3]), sys.argv[4], sys.argv[5]
    (fx, fy, cx, cy), scans = read_conf(conf)
    depth_max, trunc = 4.0, 4 * voxel
    start = time.perf_counter()
    if kind == "legacy":
        intrinsic = o3d.camera.PinholeCameraIntrinsic(640, 480, fx, fy, cx, cy)
        volume = o3d.pipelines.integration.ScalableTSDFVolume(
            voxel_length=voxel, sdf_trunc=trunc, color_type=o3d.pipelines.integration.TSDFVolumeColorType.RGB8)
        for depth_path, color_path, pose in scans:
            rgbd = o3d.geometry.RGBDImage.create_from_color_and_depth(
                o3d.io.read_image(color_path), o3d.io.read_image(depth_path), depth_scale=depth_scale,
                depth_trunc=depth_max, convert_rgb_to_intensity=False)
            volume.integrate(rgbd, intrinsic, np.linalg.inv(pose))
        integrated = time.perf_counter()
        mesh = volume.extract_triangle_mesh()
    else:
        device = o3d.core.Device("CPU:0")
        intrinsic = o3d.core.Tensor([[fx, 0, cx], [0, fy, cy], [0, 0, 1]], o3d.core.Dtype.Float64)
        grid = o3d.t.geometry.VoxelBlockGrid(
            attr_names=("tsdf", "weight", "color"),
            attr_dtypes=(o3d.core.float32, o3d.core.float32, o3d.core.float32),
            attr_channels=((1), (1), (3)), voxel_size=voxel, block_resolution=8, block_count=100000, device=device)
        for depth_path, color_path, pose in scans:
            depth = o3d.t.io.read_image(depth_path).to(device)
            color = o3d.t.io.read_image(color_path).to(device)
            extrinsic = o3d.core.Tensor(np.linalg.inv(pose), o3d.core.Dtype.Float64)
            blocks = grid.compute_unique_block_coordinates(depth, intrinsic, extrinsic, depth_scale, depth_max)
            grid.integrate(blocks, depth, color, intrinsic, extrinsic, depth_scale, depth_max)
        integrated = time.perf_counter()
        mesh = grid.extract_triangle_mesh().to_legacy()
    done = time.perf_counter()
    o3d.io.write_triangle_mesh(out, mesh)
    print(json.dumps({"frames": len(scans), "integrate_s": integrated - start, "mesh_s": done - integrated,
                      "vertices": len(mesh.vertices), "triangles": len(mesh.triangles),
                      "peak_memory_bytes": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024}))


if __name__ == "__main__":
    main()
