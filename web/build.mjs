// Copies the static files and the committed sweep results beside the compiled
// scripts: dist/ is what loom-server --web-root serves.
import { cpSync, mkdirSync } from "node:fs";

const here = new URL(".", import.meta.url);
cpSync(new URL("static/", here), new URL("dist/", here), { recursive: true });
mkdirSync(new URL("dist/results/", here), { recursive: true });
for (const name of ["sweep.csv", "methods.csv", "volume.csv"]) {
  cpSync(new URL(`../docs/results/${name}`, here), new URL(`dist/results/${name}`, here));
}
