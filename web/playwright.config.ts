// The dashboard's browser tests: Debian's Chromium driven by Playwright against a real
// loom-server (tests/loom_service.ts). CHROMIUM overrides the browser's path.
import { defineConfig } from "@playwright/test";

export default defineConfig({
  testDir: "tests",
  timeout: 300_000,
  expect: { timeout: 60_000 },
  workers: 1,
  reporter: "list",
  use: {
    headless: true,
    viewport: { width: 1280, height: 800 },
    launchOptions: { executablePath: process.env.CHROMIUM ?? "/usr/bin/chromium" },
  },
});
