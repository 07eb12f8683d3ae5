"""Reads a dataset_gen MCAP file (excavator or rope-shovel digs) with the
official `mcap` Python reader (pip install mcap) and checks schemas,
topics, messages and metadata.

Usage: python3 dataset_gen/scripts/check_mcap.py runs/dataset/dataset.mcap
"""
import json
import sys

from mcap.reader import make_reader

path = sys.argv[1]
with open(path, "rb") as f:
    reader = make_reader(f)
    summary = reader.get_summary()
    topics = {c.topic: c for c in summary.channels.values()}
    schemas = {s.id: s for s in summary.schemas.values()}
    counts = {}
    n = 0
    last_index = -1
    for schema, channel, message in reader.iter_messages(log_time_order=False):
        counts[channel.topic] = counts.get(channel.topic, 0) + 1
        assert schema.encoding == "jsonschema" and channel.message_encoding == "json"
        body = json.loads(message.data)
        if channel.topic == "/shovel/dig":
            assert schema.name == "dataset_gen.ShovelSample"
            assert body["index"] > last_index, "samples in index order"
            last_index = body["index"]
            assert len(body["x"]) == 5 and len(body["surface"]["coefficients"]) == 8
            assert all(len(row) == 8 for row in body["surface"]["coefficients"])
        elif not channel.topic.endswith("trajectory"):
            assert body["index"] > last_index, "samples in index order"
            last_index = body["index"]
            assert len(body["y"]) == 4 and len(body["input"]) == 7
        n += 1
    meta = list(reader.iter_metadata())
    assert any(m.name == "dataset_gen" and "config" in m.metadata for m in meta), "metadata record"
    print(json.dumps({
        "file": path,
        "messages": n,
        "per_topic": counts,
        "schemas": sorted(s.name for s in schemas.values()),
        "statistics_message_count": summary.statistics.message_count if summary.statistics else None,
        "metadata": [m.name for m in meta],
    }, indent=2))
