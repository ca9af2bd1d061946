// How the pages write times, sizes and enum names.

export function enumLabel(name: string | undefined, prefix: string): string {
  if (!name) return "";
  return name.startsWith(prefix) ? name.slice(prefix.length).toLowerCase() : name.toLowerCase();
}

export function shortId(id: string): string {
  return id.length > 12 ? id.slice(0, 12) : id;
}

export function time(ms: string | undefined): string {
  const value = Number(ms ?? 0);
  if (!value) return "";
  return new Date(value).toISOString().replace("T", " ").slice(0, 19);
}

export function duration(ms: number): string {
  if (!(ms > 0)) return "";
  const seconds = ms / 1000;
  if (seconds < 60) return `${seconds.toFixed(1)} s`;
  const minutes = seconds / 60;
  if (minutes < 60) return `${minutes.toFixed(1)} min`;
  return `${(minutes / 60).toFixed(1)} h`;
}

export function bytes(value: string | number | undefined): string {
  const n = Number(value ?? 0);
  if (n < 1024) return `${n} B`;
  const units = ["KiB", "MiB", "GiB", "TiB"];
  let scaled = n;
  let unit = -1;
  while (scaled >= 1024 && unit < units.length - 1) {
    scaled /= 1024;
    ++unit;
  }
  return `${scaled.toFixed(1)} ${units[unit]}`;
}
