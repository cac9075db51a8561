"""A lab's own program on mechweed's secured bus (eclipse-zenoh for Python).

    python3 lab_client.py KEYS NAME ENDPOINT
    python3 lab_client.py /etc/mechweed/keys viewer tls/192.168.1.10:7510

KEYS holds ca.pem and this program's NAME.pem and NAME.key; NAME is its identity
(viewer to watch, camera to send rows); ENDPOINT is the robot's [bus] listen, by an
address its certificate names (keys new --host/--ip).
"""
import json
import sys

import zenoh

keys, name, endpoint = sys.argv[1:4]
conf = zenoh.Config()
for key, value in {
    "mode": "peer",
    "connect/endpoints": [endpoint],
    "listen/endpoints": [],
    "scouting/multicast/enabled": False,
    "transport/link/tls/root_ca_certificate": f"{keys}/ca.pem",
    "transport/link/tls/connect_certificate": f"{keys}/{name}.pem",
    "transport/link/tls/connect_private_key": f"{keys}/{name}.key",
    "transport/link/tls/enable_mtls": True,
}.items():
    conf.insert_json5(key, json.dumps(value))

with zenoh.open(conf) as session:
    status = session.declare_subscriber("mechweed/status")
    for reply in session.get("mechweed/config/steer/speed_mps", timeout=3.0):
        print("setting:", reply.ok.payload.to_string())
    print("status:", status.recv().payload.to_string()[:200])
    # As the camera identity, rows go to mechweed/camera/row (docs/bus.md, "Row
    # estimates from a vision program").
