#!/usr/bin/env python3
"""A Loom client written from the protos alone (proto/loom/v1/service.proto), in
Python with Debian's python3-grpcio and python3-protobuf: it generates its stubs
with protoc and grpc_python_plugin (Debian's python3-grpc-tools bundles an older
protoc that rejects the protos' proto3 `optional`), uploads a quad as an OBJ mesh,
submits a render of it in a small knit (the server plans and runs the fabric's
precompute first), follows the job with WatchJob, and downloads the frame.

  /usr/bin/python3 examples/python/loom_client.py [--server HOST:PORT] [--token-file F]
                                                  [--out DIR]

Prints one JSON object with what happened; exits non-zero if anything failed.
The token comes from --token-file, else LOOM_TOKEN (none: a server without tokens).
"""
import argparse
import hashlib
import json
import os
import pathlib
import subprocess
import sys
import tempfile

import grpc

ROOT = pathlib.Path(__file__).resolve().parents[2]
CHUNK = 1 << 20  # upload chunks: at most 4 MiB (service.proto)

QUAD_OBJ = b"""# a unit quad with UVs
v -0.5 -0.5 0
v 0.5 -0.5 0
v 0.5 0.5 0
v -0.5 0.5 0
vt 0 0
vt 1 0
vt 1 1
vt 0 1
vn 0 0 1
f 1/1/1 2/2/1 3/3/1 4/4/1
"""


def generate_stubs(out):
    protos = sorted(str(p) for p in (ROOT / "proto" / "loom" / "v1").glob("*.proto"))
    subprocess.run(["protoc", "-I", str(ROOT / "proto"), "--python_out", out, "--grpc_python_out", out,
                    "--plugin=protoc-gen-grpc_python=/usr/bin/grpc_python_plugin", *protos], check=True)
    sys.path.insert(0, out)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--server", default="127.0.0.1:7450")
    parser.add_argument("--token-file")
    parser.add_argument("--out", default="out")
    args = parser.parse_args()

    with tempfile.TemporaryDirectory() as stubs:
        generate_stubs(stubs)
        from loom.v1 import job_pb2, scene_pb2, service_pb2, service_pb2_grpc

        token = pathlib.Path(args.token_file).read_text().strip() if args.token_file else os.environ.get("LOOM_TOKEN")
        metadata = [("authorization", "Bearer " + token)] if token else []
        channel = grpc.insecure_channel(args.server)
        loom = service_pb2_grpc.LoomServiceStub(channel)
        report = {}

        info = loom.GetServerInfo(service_pb2.GetServerInfoRequest(), metadata=metadata, timeout=10)
        report["server"] = {"version": info.version, "health": info.health}

        # Meshes travel as content-addressed artifacts: ask first, upload what is missing.
        sha256 = hashlib.sha256(QUAD_OBJ).hexdigest()
        missing = loom.FindMissingArtifacts(service_pb2.FindMissingArtifactsRequest(sha256=[sha256]),
                                            metadata=metadata, timeout=10).missing
        if missing:
            def upload():
                header = service_pb2.UploadArtifactRequest.Header(
                    artifact=service_pb2.ArtifactRef(sha256=sha256, size=len(QUAD_OBJ), name="mesh.obj"))
                yield service_pb2.UploadArtifactRequest(header=header)
                for offset in range(0, len(QUAD_OBJ), CHUNK):
                    yield service_pb2.UploadArtifactRequest(chunk=QUAD_OBJ[offset:offset + CHUNK])
            loom.UploadArtifact(upload(), metadata=metadata, timeout=30)
        report["uploaded_meshes"] = len(missing)

        scene = scene_pb2.SceneSpec(name="python client quad")
        cloth = scene.objects.add(name="cloth")
        cloth.mesh.artifact = sha256
        cloth.fabric.fabric.knit.SetInParent()
        cloth.fabric.precompute.spatial_resolution = 8
        cloth.fabric.precompute.view_directions = 16
        cloth.fabric.precompute.light_directions = 16
        cloth.fabric.precompute.lobes = 1
        cloth.fabric.precompute.indirect_bounces = 0  # a proto3 optional: 0 is set, not absent
        cloth.fabric.precompute.supersampling = 1
        cloth.fabric.repeat_u = cloth.fabric.repeat_v = 4
        scene.camera.position.y, scene.camera.position.z = -1.2, 1.2
        light = scene.lights.add(intensity=3.0)
        light.direction.x, light.direction.y, light.direction.z = -0.3, -0.5, 1.0
        scene.render.width, scene.render.height = 64, 48
        scene.render.format = scene_pb2.IMAGE_FORMAT_PNG
        submitted = loom.SubmitJob(service_pb2.SubmitJobRequest(render=job_pb2.RenderJob(scene=scene)),
                                   metadata=metadata, timeout=60)
        report["job"] = submitted.job.id
        report["fabric_precomputes"] = [job.id for job in submitted.dependencies]

        # WatchJob: the first event carries the log so far, the last a finished job.
        stages, events = [], 0
        for event in loom.WatchJob(service_pb2.WatchJobRequest(job_id=submitted.job.id), metadata=metadata,
                                   timeout=600):
            events += 1
            if event.job.progress.stage and (not stages or stages[-1] != event.job.progress.stage):
                stages.append(event.job.progress.stage)
            job = event.job
        report["events"] = events
        report["state"] = job_pb2.JobState.Name(job.state)
        if job.state != job_pb2.JOB_STATE_SUCCEEDED:
            report["error"] = job.error
            print(json.dumps(report))
            return 1

        frame = b"".join(chunk.chunk for chunk in loom.DownloadArtifact(
            service_pb2.DownloadArtifactRequest(sha256=job.result_artifacts[0]), metadata=metadata, timeout=60))
        if hashlib.sha256(frame).hexdigest() != job.result_artifacts[0]:
            raise RuntimeError("the downloaded frame does not match its hash")
        out = pathlib.Path(args.out)
        out.mkdir(parents=True, exist_ok=True)
        (out / "python_client_frame.png").write_bytes(frame)
        report["frame"] = {"path": str(out / "python_client_frame.png"), "bytes": len(frame),
                           "png": frame[:8] == b"\x89PNG\r\n\x1a\n"}

        # Bad input gets a clear error naming the field.
        try:
            loom.GetJob(service_pb2.GetJobRequest(job_id=""), metadata=metadata, timeout=10)
        except grpc.RpcError as error:
            report["empty_job_id"] = {"code": error.code().name, "message": error.details()}
        print(json.dumps(report))
        return 0


if __name__ == "__main__":
    sys.exit(main())
