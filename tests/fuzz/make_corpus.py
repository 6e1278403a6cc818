#!/usr/bin/env python3
"""Writes the seed corpora of the fuzz targets (tests/fuzz/corpus/TARGET/), small valid
inputs of every format plus a few known-bad ones, from luxloc's own simulator sessions
(never from ../shared: the fixtures are for checking). Usage, from the repository root
after a build:  python3 tests/fuzz/make_corpus.py build/luxloc
"""
import os, struct, subprocess, sys, tempfile, zlib

luxloc = sys.argv[1] if len(sys.argv) > 1 else "build/luxloc"
root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "corpus")


def put(target, name, data):
    d = os.path.join(root, target)
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, name), "wb") as f:
        f.write(data if isinstance(data, bytes) else data.encode())


def head(path, n):
    with open(path) as f:
        return "".join(f.readline() for _ in range(n))


def wit(ptype, words):
    p = bytes([0x55, ptype]) + struct.pack("<4h", *words)
    return p + bytes([sum(p) & 0xFF])


tmp = tempfile.mkdtemp()
walk, uwb = os.path.join(tmp, "walk"), os.path.join(tmp, "uwb")
subprocess.run([luxloc, "sim", "--out", walk, "--duration", "3", "--fixes", "2:0.3", "--frame-format", "png"], check=True, stdout=subprocess.DEVNULL)
subprocess.run([luxloc, "sim", "--out", uwb, "--scenario", "uwb", "--duration", "3", "--no-frames"], check=True, stdout=subprocess.DEVNULL)
W = lambda f: os.path.join(walk, f)

# WitMotion: a few 51 52 53 54 cycles, one with a bad checksum, garbage between.
cycle = lambda k: wit(0x51, [10 * k, -20, 2048, 2500]) + wit(0x52, [5, -k, 7, 0]) + wit(0x53, [100, 200, 300 + k, 0]) + wit(0x54, [300, -40, 500, 0])
put("fuzz_witmotion", "cycles", b"".join(cycle(k) for k in range(6)))
bad = bytearray(cycle(1)); bad[10] ^= 0xFF
put("fuzz_witmotion", "garbage_and_bad_checksum", b"\x00\x55\x12" + cycle(0) + bytes(bad) + b"\x55\x55" + cycle(2))
put("fuzz_witmotion", "acc_gyro_only", b"".join(wit(0x51, [k, 0, 2048, 0]) + wit(0x52, [0, 0, k, 0]) for k in range(8)))

# Serial IMU text lines: first byte picks the time mode (odd: device time).
imu = head(W("imu.csv"), 25)
put("fuzz_csv_imu_line", "spec_order", "\x00" + "".join(imu.splitlines(True)[1:]))
put("fuzz_csv_imu_line", "header_device_time", "\x01" + imu)
put("fuzz_csv_imu_line", "tabs_comments_crlf", "\x02# comment\r\n" + imu.replace(",", "\t").replace("\n", "\r\n") + "1,2,3\nx,y\n")
put("fuzz_csv_imu_line", "no_mag", "\x04t,ax,ay,az,gx,gy,gz\n" + "".join(",".join(l.split(",")[:7]) + "\n" for l in imu.splitlines()[1:]))

# UWB lines: first byte odd = DWM1001, even = TOF+AOA.
dist = "DIST,4,AN0,022E,7.94,8.03,0.00,3.44,AN1,9280,7.95,0.00,0.00,5.68,AN2,DCAE,0.00,8.03,0.00,7.76,AN3,5431,0.00,0.00,0.00,4.98,POS,3.10,4.20,1.00,87\r\n"
put("fuzz_uwb_lines", "dwm_lec", "\x01dwm> lec\r\n" + dist * 3 + "POS,3.1,4.2,1.0,91\r\n" + "DIST,2,AN0,022E,1,2,0,abc\n")
put("fuzz_uwb_lines", "tof_aoa", "\x00anchor,range_m,aoa_rad\n# c\n1,3.52,0.71\n2,4.10\n3,-1,0.2\n1,nan,0\n" + "".join(",".join(l.split(",")[1:]) for l in head(os.path.join(uwb, "uwb.csv"), 20).splitlines(True)[1:]))

# Session CSVs: first line names the file.
for kind in ["imu", "frames", "fixes", "groundtruth"]:
    put("fuzz_session_csv", kind, kind + "\n" + head(W(kind + ".csv"), 30))
put("fuzz_session_csv", "uwb", "uwb\n" + head(os.path.join(uwb, "uwb.csv"), 30))
put("fuzz_session_csv", "odom", "odom\nt,dist_m,dyaw_rad\n0.1,0.2,0.01\n0.2,0.25,-0.02\n0.2,0.1,0\n0.3,1e30,0\n")
put("fuzz_session_csv", "frames_bad", "frames\nt,file\n0.01,frames/bad.png\n0.02,frames/missing.png\n0.01,../x.png\n")
put("fuzz_session_csv", "imu_dirty", "imu\n" + head(W("imu.csv"), 8) + "0.2,1e30,0,9.8,0,0,0\n0.2,nan,0,9.8,0,0,0\n0.19,0,0\n0.3,0,0,9.8,0,0,1e9,,,\n")
put("fuzz_session_csv", "poses_csv", "poses\nt,x,y,z,yaw,sigma_x,sigma_y,roll,pitch,n_eff,leds,mode\n0.1,1,2,1,0.1,0.2,0.2,0,0,900.0,2,fused\n0.2,1.1,2,1,,,,0,0,,0,imu-only\n")
put("fuzz_session_csv", "poses_tum", "poses\n# tum\n0.1 1 2 1 0 0 0 1\n0.2 1.1 2 1 0 0 0.1 0.995\n")

# YAML readers: first line names the reader.
for kind, f in [("ledmap", "ledmap.yaml"), ("camera", "camera.yaml")]:
    put("fuzz_yaml", kind, kind + "\n" + open(W(f)).read())
put("fuzz_yaml", "session_anchors", "session\n" + open(os.path.join(uwb, "session.yaml")).read())
put("fuzz_yaml", "ledmap_anchors", "ledmap\n" + open(os.path.join(uwb, "session.yaml")).read())
put("fuzz_yaml", "imucalib", "imucalib\n%YAML:1.0\n---\nmethod: static\ngyro_bias: [ 0.001, -0.002, 0.0005 ]\n"
    "acc_bias: [ 0.01, 0.02, -0.03 ]\nacc_scale: [ 1.0, 1.0, 1.0 ]\n")
put("fuzz_yaml", "not_a_map", "ledmap\n%YAML:1.0\n---\nleds: 3\n")

# Config files (TOML/INI) for a subcommand.
put("fuzz_config", "run", "run\n[run]\nplayback=\"walk\"\nparticles=500\nfilter=\"pf\"\nudp=[\"127.0.0.1:9870\"]\nrealtime=false\n")
put("fuzz_config", "sim", "sim\n[sim]\nout=\"x\"\nscenario=\"dense\"\nduration=5.5\nblackout=[\"1:2\"]\n")
put("fuzz_config", "bad", "run\n[run]\nparticles=-3\nunknown_key=1\n[[run]]\n")

# Pose formatter: raw binary poses (t, x, y, z, yaw, roll, pitch, sx, sy, n_eff, leds, seq, mode).
def pose(t, vals, leds, seq, mode):
    return struct.pack("<q9dIQ", t, *vals, leds, seq) + mode
put("fuzz_pose_format", "normal", pose(12_345_678_901, [1.5, -2.25, 1.0, 0.3, 0.01, -0.02, 0.12, 0.15, 812.5], 3, 41, b"fused"))
put("fuzz_pose_format", "unknowns", pose(-5, [float("nan"), 1e308, -0.0, float("inf"), 0, 0, float("nan"), 5e-324, float("nan")], 0, 2**64 - 1, b"a,b\nc"))

# Frames: a tiny PNG, a cut one, and a low-quality JPEG of the walk (small seeds mutate faster).
def tiny_png():
    raw = b"".join(b"\x00" + bytes([(x * 16 + y) & 255 for x in range(8)]) for y in range(4))
    chunk = lambda t, d: struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d))
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", 8, 4, 8, 0, 0, 0, 0)) + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b"")
put("fuzz_image", "tiny_png", tiny_png())
put("fuzz_image", "cut_png", tiny_png()[:60])
subprocess.run([luxloc, "sim", "--out", os.path.join(tmp, "jpg"), "--duration", "0.2", "--frame-format", "jpg", "--jpeg-quality", "30"], check=True, stdout=subprocess.DEVNULL)
jd = os.path.join(tmp, "jpg", "frames")
put("fuzz_image", "frame_jpg", open(os.path.join(jd, sorted(os.listdir(jd))[0]), "rb").read())

# Whole sessions: session.yaml, ledmap, camera, imu, frames, uwb, fixes joined by "=====".
# The frames the target provides are 64x48 (frames/000000.png..000002.png).
cam = open(W("camera.yaml")).read()
import re
cam64 = re.sub(r"image_width: *\d+", "image_width: 64", re.sub(r"image_height: *\d+", "image_height: 48", cam))
frames = "t,file\n0.05,frames/000000.png\n0.10,frames/000001.png\n0.15,frames/000002.png\n"
sep = "\n=====\n"
put("fuzz_session", "walk", sep.join([open(W("session.yaml")).read(), open(W("ledmap.yaml")).read(), cam64, head(W("imu.csv"), 40), frames, "", head(W("fixes.csv"), 3)]))
put("fuzz_session", "uwb", sep.join([open(os.path.join(uwb, "session.yaml")).read(), "", "", head(os.path.join(uwb, "imu.csv"), 40), "", head(os.path.join(uwb, "uwb.csv"), 30), ""]))
put("fuzz_session", "imu_only", sep.join(["", "", "", head(W("imu.csv"), 60)]))
print("corpora written to", root)
