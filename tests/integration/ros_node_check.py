"""The ROS side of ros_node_test.sh: publishes frames to deepsea_ros and checks what comes back,
writes a bag of the frames, and checks deepsea_rosbag's output bag. Modes:
  live IN REF            frames of IN to the node, each output against REF's PNG
  write_bag IN BAG [MS]  IN's frames into BAG (depth stamped MS milliseconds after colour)
  read_bag IN REF BAG    BAG's rendered images against REF's PNGs
"""
import glob
import os
import sys
import threading
import time

import numpy as np
import OpenImageIO as oiio
import rospy
from diagnostic_msgs.msg import DiagnosticArray
from sensor_msgs.msg import CameraInfo, Image

FRAME_ID = "camera_optical"


def read(path, kind):
    return oiio.ImageInput.open(path).read_image(kind)


def frames(folder):
    """(rgb codes HxWx3, depth metres HxW) of each scene frame, in order."""
    out = []
    for png in sorted(glob.glob(os.path.join(folder, "frame_*[0-9].png"))):
        rgb = read(png, "uint8")
        depth = read(png[:-4] + "_depth.exr", "float")
        out.append((rgb, depth.reshape(depth.shape[0], depth.shape[1])))
    return out


def image(stamp, encoding, width, height, step, data):
    m = Image()
    m.header.stamp = stamp
    m.header.frame_id = FRAME_ID
    m.encoding, m.width, m.height, m.step, m.data = encoding, width, height, step, data
    return m


def colour_msg(stamp, rgb, encoding):
    h, w, _ = rgb.shape
    px = {"rgb8": rgb, "bgr8": rgb[..., ::-1],
          "rgba8": np.dstack([rgb, np.full((h, w, 1), 77, np.uint8)])}[encoding]
    px = np.ascontiguousarray(px)
    return image(stamp, encoding, w, h, px.shape[2] * w, px.tobytes())


def depth_msg(stamp, depth):
    h, w = depth.shape
    return image(stamp, "32FC1", w, h, 4 * w, depth.astype("<f4").tobytes())


def info_msg(stamp, w, h, fx=120.0):
    m = CameraInfo()
    m.header.stamp = stamp
    m.header.frame_id = FRAME_ID
    m.width, m.height = w, h
    m.K = [fx, 0, w / 2, 0, fx, h / 2, 0, 0, 1]
    return m


def codes(msg):
    assert msg.encoding == "rgb8" and msg.step == 3 * msg.width, (msg.encoding, msg.step)
    return np.frombuffer(msg.data, np.uint8).reshape(msg.height, msg.width, 3)


def check_image(msg, ref_png, what):
    got, want = codes(msg).astype(int), read(ref_png, "uint8").astype(int)
    assert got.shape == want.shape, (what, got.shape, want.shape)
    diff = np.abs(got - want)
    assert diff.max() <= 1, "%s: %d pixel(s) differ by more than one code (max %d)" % (
        what, int((diff > 1).sum()), diff.max())
    assert want.max() > 20, (what, "reference too dark to tell anything")


def check_depth(msg, depth, what):
    assert msg.encoding == "32FC1", msg.encoding
    got = np.frombuffer(msg.data, "<f4").reshape(msg.height, msg.width)
    valid = np.isfinite(depth) & (depth > 0)
    assert np.allclose(got[valid], depth[valid], rtol=1e-6), what
    assert (got[~valid] == 0).all(), what


def live(folder, ref):
    rospy.init_node("deepsea_check", anonymous=True, disable_signals=True)
    lock = threading.Condition()
    got, diag = {}, {}

    def keep(kind):
        def cb(msg):
            with lock:
                got.setdefault(msg.header.stamp.to_nsec(), {})[kind] = msg
                lock.notify_all()
        return cb

    def on_diag(msg):
        with lock:
            for s in msg.status:
                if "deep-sea camera" in s.name:
                    diag.clear()
                    diag.update({kv.key: kv.value for kv in s.values})
            lock.notify_all()

    subs = [rospy.Subscriber("/deepsea/" + k, c, keep(k), queue_size=20)
            for k, c in (("image_raw", Image), ("camera_info", CameraInfo), ("depth", Image),
                         ("backscatter", Image))]
    subs.append(rospy.Subscriber("/diagnostics", DiagnosticArray, on_diag, queue_size=20))
    pc = rospy.Publisher("/camera/image_raw", Image, queue_size=20)
    pd = rospy.Publisher("/camera/depth/image_raw", Image, queue_size=20)
    pi = rospy.Publisher("/camera/camera_info", CameraInfo, queue_size=20)
    deadline = time.time() + 20
    while not (all(p.get_num_connections() for p in (pc, pd, pi)) and
               all(s.get_num_connections() for s in subs)):
        assert time.time() < deadline, "the node did not connect"
        time.sleep(0.05)

    def wait(pred, what, seconds=10):
        end = time.time() + seconds
        with lock:
            while not pred():
                left = end - time.time()
                assert left > 0, "timed out waiting for " + what
                lock.wait(left)

    def send(stamp, c, d, info=None):
        if info is not None:
            pi.publish(info)
        pd.publish(d)
        pc.publish(c)

    # Good frames, each in another colour encoding, one at a time.
    encodings = ["rgb8", "bgr8", "rgba8"]
    refs = sorted(glob.glob(os.path.join(ref, "frame_*.png")))
    fr = frames(folder)
    assert len(fr) == len(refs) == 3, (len(fr), refs)
    for i, ((rgb, depth), png) in enumerate(zip(fr, refs)):
        stamp = rospy.Time(100 + i, 250)
        h, w, _ = rgb.shape
        send(stamp, colour_msg(stamp, rgb, encodings[i]), depth_msg(stamp, depth),
             info_msg(stamp, w, h))
        key = stamp.to_nsec()
        wait(lambda: key in got and {"image_raw", "camera_info", "depth", "backscatter"} <= set(got[key]),
             "frame %d" % i)
        out = got[key]
        for k in ("image_raw", "camera_info", "depth", "backscatter"):
            assert out[k].header.stamp == stamp and out[k].header.frame_id == FRAME_ID, k
        check_image(out["image_raw"], png, "frame %d (%s)" % (i, encodings[i]))
        check_depth(out["depth"], depth, "frame %d depth" % i)
        k = out["camera_info"]
        assert (k.width, k.height) == (w, h) and list(k.K) == [120, 0, 80, 0, 120, 60, 0, 0, 1], k

    # Malformed: wrong encoding, colour and depth of different sizes, empty data.
    rgb, depth = fr[0]
    h, w, _ = rgb.shape
    bad = []
    s = rospy.Time(200, 0)
    bad.append((s, image(s, "mono8", w, h, w, bytes(w * h)), depth_msg(s, depth)))
    s = rospy.Time(201, 0)
    bad.append((s, colour_msg(s, rgb, "rgb8"), depth_msg(s, depth[::2, ::2].copy())))
    s = rospy.Time(202, 0)
    bad.append((s, image(s, "rgb8", w, h, 3 * w, b""), depth_msg(s, depth)))
    for s, c, d in bad:
        send(s, c, d)
        time.sleep(0.1)
    # alive: the next good frame is rendered; a camera_info of another camera is an error,
    # reported once for the two frames that follow it
    for n, sec in enumerate((203, 204, 205)):
        s = rospy.Time(sec, 0)
        send(s, colour_msg(s, rgb, "rgb8"), depth_msg(s, depth),
             info_msg(s, w, h, 120.0 if n == 0 else 150.0))
        wait(lambda: s.to_nsec() in got and "image_raw" in got[s.to_nsec()], "frame at %d" % sec)
        check_image(got[s.to_nsec()]["image_raw"], refs[0], "frame after malformed ones")
    for s, _, _ in bad:
        assert s.to_nsec() not in got, "a malformed frame was published"
    wait(lambda: diag.get("rendered") == "6" and diag.get("malformed") == "3", "diagnostics")
    assert diag["colour_received"] == "9" and diag["depth_received"] == "9", diag
    assert int(diag["mismatched"]) >= 2 and diag["unpaired"] == "0", diag
    print("live: ok", diag)


def write_bag(folder, path, depth_offset_ms="0"):
    import rosbag
    off = rospy.Duration.from_sec(float(depth_offset_ms) * 1e-3)
    with rosbag.Bag(path, "w") as bag:
        for i, (rgb, depth) in enumerate(frames(folder)):
            s = rospy.Time(100 + i, 250)
            h, w, _ = rgb.shape
            bag.write("/camera/depth/image_raw", depth_msg(s + off, depth), s + off)
            bag.write("/camera/camera_info", info_msg(s, w, h), s)
            bag.write("/camera/image_raw", colour_msg(s, rgb, "bgr8"), s)


def read_bag(folder, ref, path):
    import rosbag
    refs = sorted(glob.glob(os.path.join(ref, "frame_*.png")))
    fr = frames(folder)
    seen, topics = 0, {}
    with rosbag.Bag(path) as bag:
        for topic, msg, t in bag.read_messages():
            topics[topic] = topics.get(topic, 0) + 1
            if topic == "/deepsea/image_raw":
                i = msg.header.stamp.secs - 100
                assert msg.header.stamp == rospy.Time(100 + i, 250) and t == msg.header.stamp
                assert msg.header.frame_id == FRAME_ID
                check_image(msg, refs[i], "bag frame %d" % i)
                seen += 1
            if topic == "/deepsea/depth":
                check_depth(msg, fr[msg.header.stamp.secs - 100][1], "bag depth")
    assert seen == 3, topics
    for t in ("/camera/image_raw", "/camera/depth/image_raw", "/camera/camera_info",
              "/deepsea/camera_info", "/deepsea/depth"):
        assert topics.get(t) == 3, (t, topics)
    print("bag: ok", topics)


if __name__ == "__main__":
    mode, args = sys.argv[1], sys.argv[2:]
    {"live": live, "write_bag": write_bag, "read_bag": read_bag}[mode](*args)
