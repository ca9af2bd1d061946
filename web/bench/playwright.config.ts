// The dashboard's load benchmark (not a test: it asserts nothing and prints figures):
//   cd web && npx playwright test --config bench/playwright.config.ts
// The browser tests' browser and options, with a longer timeout.
import { defineConfig } from "@playwright/test";

import tests from "../playwright.config";

export default defineConfig({ ...tests, testDir: ".", timeout: 900_000 });
