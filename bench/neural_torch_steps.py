#!/usr/bin/env python3
"""Times the neural method's training step in PyTorch (Debian's python3-torch, the
libtorch that libtorch-dev links), for the choice between libtorch and Loom's own
Eigen trainer (core/methods/neural/neural_fabric.cpp): the same model, batch and
optimiser — a latent of C numbers per texel for the standard knit's 1 365 texels
(32² down to 1²), a decoder (C + 4) → H → H → 3 with ReLU, 1 024 samples a step,
Adam — on random data (the step's cost does not depend on the values).

    python3 bench/neural_torch_steps.py [--steps 2000] [--threads 2] [--channels 8] [--hidden 32]

Prints seconds per step; Loom's own is `loom-lab fit`'s seconds over its steps
(docs/methods/neural.md)."""
import argparse
import time

import torch

parser = argparse.ArgumentParser()
parser.add_argument("--steps", type=int, default=2000)
parser.add_argument("--threads", type=int, default=2)
parser.add_argument("--channels", type=int, default=8)
parser.add_argument("--hidden", type=int, default=32)
args = parser.parse_args()
torch.set_num_threads(args.threads)
torch.manual_seed(0)

texels = sum(4 ** j for j in range(6))  # 32², 16², …, 1²
latents = torch.nn.Parameter(torch.rand(texels, args.channels) - 0.5)
decoder = torch.nn.Sequential(
    torch.nn.Linear(args.channels + 4, args.hidden), torch.nn.ReLU(),
    torch.nn.Linear(args.hidden, args.hidden), torch.nn.ReLU(),
    torch.nn.Linear(args.hidden, 3))
optimiser = torch.optim.Adam([latents, *decoder.parameters()], lr=5e-3)
directions = torch.rand(81 + 64, 2) - 0.5
targets = torch.rand(texels, 3)


def step():
    texel = torch.randint(0, texels, (1024,))
    view = torch.randint(0, 81, (1024,))
    light = torch.randint(81, 81 + 64, (1024,))
    x = torch.cat([latents[texel], directions[view], directions[light]], dim=1)
    loss = ((decoder(x) - targets[texel]) ** 2).mean()
    optimiser.zero_grad()
    loss.backward()
    optimiser.step()


for _ in range(50):  # warm up
    step()
start = time.perf_counter()
for _ in range(args.steps):
    step()
seconds = time.perf_counter() - start
print(f"torch {torch.__version__}, {args.threads} threads, C={args.channels} H={args.hidden}: "
      f"{1e3 * seconds / args.steps:.3f} ms a step ({args.steps} steps, {seconds:.1f} s)")
