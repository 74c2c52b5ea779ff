#!/usr/bin/env python3
"""Writes a TUM-layout folder (rgb.txt, depth.txt, camera-intrinsics.txt) as a ROS 1 bag with
Debian's python3-rosbag, an implementation of the format independent of ours, for the tests
of fine2coarse's bag reader (src/f2c/io/readers_rosbag.cc).

  write_rosbag.py FOLDER OUT.bag [--layout tum|realsense] [--compression none|bz2|lz4]
                  [--intrinsics fx,fy,cx,cy] [--extra-color-topic TOPIC]
                  [--color-camera fx,fy,cx,cy,tx,ty,tz] [--repeat N] [--compressed-color]
                  [--no-camera-info] [--color-encoding rgb8|bgr8|rgba8|mono8|...]

tum: TUM's own bags' topics: /camera/rgb/image_color (rgb8), /camera/depth/image (32FC1,
metres), /camera/{rgb,depth}/camera_info. realsense: rs-record's layout:
/device_0/sensor_0/Depth_0/image/data (mono16 in the folder's units, written as the Depth
Units option), /device_0/sensor_1/Color_0/image/data (rgb8), each stream's info/camera_info
and tf/0 (identity: the folder's colour and depth share a camera). Exit 77 where python3-rosbag
or the ROS message modules are missing (the tests skip).
"""
import argparse
import io
import os
import struct
import sys

try:
    import numpy as np
    from PIL import Image as PILImage
    import rosbag
    import rospy
    from geometry_msgs.msg import Transform, TransformStamped
    from sensor_msgs.msg import CameraInfo, CompressedImage, Image
    from std_msgs.msg import Float32
    from tf2_msgs.msg import TFMessage
except ImportError as e:  # pragma: no cover
    print(f"write_rosbag.py: {e} (apt-get install python3-rosbag python3-sensor-msgs python3-geometry-msgs python3-pil)",
          file=sys.stderr)
    sys.exit(77)


def read_png(path):
    """The PNG's pixels: H x W x 3 (or 4) uint8 colour, or H x W uint16 depth."""
    pixels = np.array(PILImage.open(path))
    if pixels.dtype != np.uint8:
        pixels = pixels.astype(np.uint16)
    return pixels, pixels.shape[1], pixels.shape[0]


def read_list(path):
    out = []
    for line in open(path):
        line = line.strip()
        if line and not line.startswith("#"):
            stamp, name = line.split()[:2]
            out.append((stamp, name))
    return out


def camera_info(k, width, height, stamp, frame):
    m = CameraInfo()
    m.header.stamp = stamp
    m.header.frame_id = frame
    m.width, m.height = width, height
    m.distortion_model = "plumb_bob"
    m.D = [0.0] * 5
    m.K = [k[0], 0, k[2], 0, k[1], k[3], 0, 0, 1]
    m.R = [1, 0, 0, 0, 1, 0, 0, 0, 1]
    m.P = [k[0], 0, k[2], 0, 0, k[1], k[3], 0, 0, 0, 1, 0]
    return m


def image(pixels, encoding, stamp, frame, seq):
    m = Image()
    m.header.seq = seq
    m.header.stamp = stamp
    m.header.frame_id = frame
    m.height, m.width = pixels.shape[0], pixels.shape[1]
    m.encoding = encoding
    m.is_bigendian = 0
    m.step = pixels.strides[0]
    m.data = pixels.tobytes()
    return m


def main():
    p = argparse.ArgumentParser()
    p.add_argument("folder")
    p.add_argument("out")
    p.add_argument("--layout", default="tum", choices=["tum", "realsense"])
    p.add_argument("--compression", default="none", choices=["none", "bz2", "lz4"])
    p.add_argument("--no-camera-info", action="store_true")
    p.add_argument("--color-encoding", default="rgb8")
    p.add_argument("--color-camera", help="fx,fy,cx,cy,tx,ty,tz: the colour camera's info and its place in the "
                   "depth camera's frame (realsense: the colour stream's tf/0; tum: /tf_static)")
    p.add_argument("--compressed-depth", nargs="?", const=0, type=int, help="depth (TUM layout) as 32FC1 "
                   "compressedDepth: inverse depth quantised into a 16-bit PNG, as ROS's compressed_depth_image_transport "
                   "writes it; the value is the header's format field (0, inverse depth; others for damaged bags)")
    p.add_argument("--compressed-color", action="store_true", help="colour as sensor_msgs/CompressedImage holding "
                   "the folder's own image files' bytes (JPEG or PNG), on <colour topic>/compressed")
    p.add_argument("--repeat", type=int, default=1, help="the frames this many times, one after another "
                   "(bench/recording_bench.sh: a large bag)")
    p.add_argument("--extra-color-topic", help="a second colour image topic with the same images")
    p.add_argument("--intrinsics", help="fx,fy,cx,cy (default: the folder's camera-intrinsics.txt)")
    a = p.parse_args()
    if a.intrinsics:
        k = tuple(float(v) for v in a.intrinsics.split(","))
    else:
        rows = [l.split() for l in open(os.path.join(a.folder, "camera-intrinsics.txt")) if l.strip()]
        k = (float(rows[0][0]), float(rows[1][1]), float(rows[0][2]), float(rows[1][2]))
    colors = read_list(os.path.join(a.folder, "rgb.txt"))
    depths = read_list(os.path.join(a.folder, "depth.txt"))
    tum = a.layout == "tum"
    depth_topic = "/camera/depth/image" if tum else "/device_0/sensor_0/Depth_0/image/data"
    color_topic = "/camera/rgb/image_color" if tum else "/device_0/sensor_1/Color_0/image/data"
    depth_info = "/camera/depth/camera_info" if tum else "/device_0/sensor_0/Depth_0/info/camera_info"
    color_info = "/camera/rgb/camera_info" if tum else "/device_0/sensor_1/Color_0/info/camera_info"
    with rosbag.Bag(a.out, "w", compression=a.compression) as bag:
        t0 = rospy.Time.from_sec(float(colors[0][0]) - 0.01)
        color_camera = [float(v) for v in a.color_camera.split(",")] if a.color_camera else None
        if not tum:
            bag.write("/device_0/sensor_0/option/Depth Units/value", Float32(1.0 / 5000.0), t0)
            for topic in ("/device_0/sensor_0/Depth_0/tf/0", "/device_0/sensor_1/Color_0/tf/0"):
                t = Transform()
                t.rotation.w = 1.0
                if color_camera and "Color" in topic:
                    t.translation.x, t.translation.y, t.translation.z = color_camera[4:7]
                bag.write(topic, t, t0)
        events = [(float(s), "c", s, n, i) for i, (s, n) in enumerate(colors)]
        events += [(float(s), "d", s, n, i) for i, (s, n) in enumerate(depths)]
        events.sort()
        span = int(events[-1][0] - events[0][0]) + 1
        repeated = []
        for r in range(a.repeat):  # each repeat `span` whole seconds later
            for e in events:
                sec, frac = e[2].split(".")
                repeated.append((e[0] + r * span, e[1], f"{int(sec) + r * span}.{frac}", e[3], e[4]))
        events = repeated
        depth_frame, color_frame = ("camera_depth_optical_frame", "camera_rgb_optical_frame") if tum else ("depth", "color")
        if tum and color_camera:
            tfs = TFMessage()
            for child, t in ((depth_frame, (0.0, 0.0, 0.0)), (color_frame, tuple(color_camera[4:7]))):
                ts = TransformStamped()
                ts.header.stamp = t0
                ts.header.frame_id = "camera_link"
                ts.child_frame_id = child
                ts.transform.translation.x, ts.transform.translation.y, ts.transform.translation.z = t
                ts.transform.rotation.w = 1.0
                tfs.transforms.append(ts)
            bag.write("/tf_static", tfs, t0)
        infos_written = False
        for _, kind, s, name, i in events:
            stamp = rospy.Time(int(s.split(".")[0]), int(round(float("0." + s.split(".")[1]) * 1e9)))
            pixels, w, h = read_png(os.path.join(a.folder, name))
            if not infos_written and not a.no_camera_info:
                bag.write(depth_info, camera_info(k, w, h, stamp, depth_frame), stamp)
                kc = tuple(float(v) for v in a.color_camera.split(",")[:4]) if a.color_camera else k
                bag.write(color_info, camera_info(kc, w, h, stamp, color_frame), stamp)
                infos_written = True
            if kind == "d" and a.compressed_depth is not None:
                # compressed_depth_image_transport's 32FC1: a header (format 0, inverse depth;
                # float32 A, B) and a 16-bit PNG of q = A / z + B (0: no depth).
                quant_a, quant_b = 100.0 * 101.0, 1.0 - 100.0 * 101.0 / 10.0
                z = pixels.astype(np.float64) / 5000.0
                q = np.where(z > 0, np.rint(quant_a / np.where(z > 0, z, 1.0) + quant_b), 0).astype(np.uint16)
                png = io.BytesIO()
                PILImage.fromarray(q).save(png, format="PNG")
                msg = CompressedImage()
                msg.header.seq = i
                msg.header.stamp = stamp
                msg.header.frame_id = depth_frame
                msg.format = "32FC1; compressedDepth"
                msg.data = struct.pack("<iff", a.compressed_depth, quant_a, quant_b) + png.getvalue()
                bag.write(depth_topic + "/compressedDepth", msg, stamp)
            elif kind == "d":
                if tum:
                    metres = (pixels.astype(np.float64) / 5000.0).astype(np.float32)
                    msg = image(metres, "32FC1", stamp, depth_frame, i)
                else:
                    msg = image(pixels, "mono16", stamp, depth_frame, i)
                bag.write(depth_topic, msg, stamp)
            elif a.compressed_color:
                msg = CompressedImage()
                msg.header.seq = i
                msg.header.stamp = stamp
                msg.header.frame_id = color_frame
                data = open(os.path.join(a.folder, name), "rb").read()
                msg.format = "png" if data[:4] == b"\x89PNG" else "jpeg"
                msg.data = data
                bag.write(color_topic + "/compressed", msg, stamp)
            else:
                rgb = pixels[:, :, :3]
                enc = a.color_encoding
                if enc == "bgr8":
                    rgb = rgb[:, :, ::-1]
                elif enc == "rgba8":
                    rgb = np.dstack([rgb, np.full(rgb.shape[:2], 255, np.uint8)])
                elif enc != "rgb8":  # mono8, and encodings the reader refuses (bayer_rggb8, ...)
                    rgb = rgb[:, :, 1]
                msg = image(np.ascontiguousarray(rgb), enc, stamp, color_frame, i)
                bag.write(color_topic, msg, stamp)
                if a.extra_color_topic:
                    bag.write(a.extra_color_topic, msg, stamp)


if __name__ == "__main__":
    main()
