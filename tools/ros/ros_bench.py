"""The client side of scripts/ros_bench.sh: publishes RGB-D frames to deepsea_ros at a rate,
each stamped with the wall time it is sent, and measures what comes back: frames out per
second, latency (arrival of the rendered image minus its stamp), and the node's counts.
  ros_bench.py FOLDER RATE_HZ SECONDS
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
from sensor_msgs.msg import Image


def msgs(folder):
    out = []
    for png in sorted(glob.glob(os.path.join(folder, "frame_*[0-9].png"))):
        rgb = oiio.ImageInput.open(png).read_image("uint8")
        d = oiio.ImageInput.open(png[:-4] + "_depth.exr").read_image("float")
        h, w, _ = rgb.shape
        c, z = Image(), Image()
        c.encoding, c.width, c.height, c.step, c.data = "rgb8", w, h, 3 * w, rgb.tobytes()
        z.encoding, z.width, z.height, z.step = "32FC1", w, h, 4 * w
        z.data = np.ascontiguousarray(d.reshape(h, w), "<f4").tobytes()
        out.append((c, z))
    return out


def main(folder, rate, seconds):
    rate, seconds = float(rate), float(seconds)
    rospy.init_node("deepsea_bench", anonymous=True, disable_signals=True)
    lock = threading.Lock()
    lat, arrivals, diag = [], [], {}

    def on_image(m):
        now = time.time()
        with lock:
            lat.append(now - m.header.stamp.to_sec())
            arrivals.append(now)

    def on_diag(m):
        for s in m.status:
            if "deep-sea camera" in s.name:
                diag.update({kv.key: kv.value for kv in s.values})

    sub = rospy.Subscriber("/deepsea/image_raw", Image, on_image, queue_size=4,
                           buff_size=1 << 24, tcp_nodelay=True)
    rospy.Subscriber("/diagnostics", DiagnosticArray, on_diag, queue_size=4)
    pc = rospy.Publisher("/camera/image_raw", Image, queue_size=1, tcp_nodelay=True)
    pd = rospy.Publisher("/camera/depth/image_raw", Image, queue_size=1, tcp_nodelay=True)
    while not (pc.get_num_connections() and pd.get_num_connections() and
               sub.get_num_connections()):
        time.sleep(0.05)
    frames = msgs(folder)
    period, sent = 1.0 / rate, 0
    start = time.time()
    warm = start + 1.0  # the first second (exposure, first allocations) is not counted
    while time.time() - start < seconds + 1.0:
        c, z = frames[sent % len(frames)]
        stamp = rospy.Time.from_sec(time.time())
        c.header.stamp = z.header.stamp = stamp
        pd.publish(z)
        pc.publish(c)
        sent += 1
        time.sleep(max(0.0, start + sent * period - time.time()))
    time.sleep(0.5)
    with lock:
        keep = [i for i, t in enumerate(arrivals) if t >= warm]
        l = np.array([lat[i] for i in keep]) * 1e3
        t = [arrivals[i] for i in keep]
    out_rate = (len(t) - 1) / (t[-1] - t[0]) if len(t) > 1 else 0.0
    print("input %.1f Hz (%d frames sent), output %.1f Hz; latency ms: median %.1f, p95 %.1f, "
          "max %.1f (one input period: %.1f ms); node: rendered %s, dropped %s, unpaired %s, "
          "render ms mean %s" % (sent / (time.time() - start - 0.5), sent, out_rate,
                                 np.median(l), np.percentile(l, 95), l.max(), period * 1e3,
                                 diag.get("rendered"), diag.get("dropped"),
                                 diag.get("unpaired"), diag.get("render_ms_mean")))


if __name__ == "__main__":
    main(*sys.argv[1:])
