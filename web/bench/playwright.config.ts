// The dashboard's load benchmark (not a test: it asserts nothing and prints figures):
//   cd web && npx playwright test --config bench/playwright.config.ts
import { defineConfig } from "@playwright/test";

export default defineConfig({
  testDir: ".",
  timeout: 900_000,
  workers: 1,
  reporter: "list",
  use: {
    headless: true,
    viewport: { width: 1280, height: 800 },
    launchOptions: { executablePath: process.env.CHROMIUM ?? "/usr/bin/chromium" },
  },
});
