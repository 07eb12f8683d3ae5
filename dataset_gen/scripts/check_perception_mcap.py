#!/usr/bin/env python3
"""Reads a `perceive --mcap` file with the official MCAP reader and decodes
each foxglove.PointCloud with the protobuf schema stored in the file, as
Foxglove does: prints topic, frame, fields, point count and first point.

    pip install mcap mcap-protobuf-support
    python3 dataset_gen/scripts/check_perception_mcap.py runs/typical.mcap
"""

import struct
import sys

from mcap.reader import make_reader
from mcap_protobuf.decoder import DecoderFactory

with open(sys.argv[1], "rb") as f:
    reader = make_reader(f, decoder_factories=[DecoderFactory()])
    for schema, channel, msg, cloud in reader.iter_decoded_messages():
        n = len(cloud.data) // cloud.point_stride
        first = struct.unpack_from("<fff", cloud.data, 0) if n else ()
        print(channel.topic, schema.name, cloud.frame_id, [fl.name for fl in cloud.fields], n,
              tuple(round(v, 4) for v in first))
