// Short polling: `refresh` now, then `intervalMs` after each refresh ends (so a slow
// server is never asked twice at once), until the returned stop is called. A
// failed refresh goes to `onError`; polling goes on.

export type Stop = () => void;

export function poll(refresh: () => Promise<void>, intervalMs: number, onError: (error: unknown) => void): Stop {
  let stopped = false;
  let timer: number | undefined;
  const tick = async () => {
    try {
      await refresh();
    } catch (error) {
      if (!stopped) onError(error);
    }
    if (!stopped) timer = window.setTimeout(tick, intervalMs);
  };
  void tick();
  return () => {
    stopped = true;
    window.clearTimeout(timer);
  };
}
