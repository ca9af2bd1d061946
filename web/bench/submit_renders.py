#!/usr/bin/env python3
"""Submits N render jobs of a scene spec in one process (the `loom` CLI costs ~0.4 s a
process): what the dashboard's load benchmark (web/bench/load.spec.ts) fills a queue
with. Stubs come from examples/python/loom_client.py.

  /usr/bin/python3 web/bench/submit_renders.py --server HOST:PORT --token-file F --count N SCENE.json
"""
import argparse
import json
import pathlib
import sys
import tempfile

import grpc

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "examples" / "python"))
from loom_client import generate_stubs  # noqa: E402


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--server", required=True)
    parser.add_argument("--token-file", required=True)
    parser.add_argument("--count", type=int, required=True)
    parser.add_argument("scene")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as stubs:
        generate_stubs(stubs)
        from google.protobuf import json_format
        from loom.v1 import service_pb2, service_pb2_grpc

        token = pathlib.Path(args.token_file).read_text().strip()
        stub = service_pb2_grpc.LoomServiceStub(grpc.insecure_channel(args.server))
        request = service_pb2.SubmitJobRequest()
        json_format.Parse(json.dumps({"render": {"scene": json.loads(pathlib.Path(args.scene).read_text())}}),
                          request)
        for _ in range(args.count):
            stub.SubmitJob(request, metadata=[("authorization", "Bearer " + token)])
    print(json.dumps({"submitted": args.count}))


if __name__ == "__main__":
    main()
