// The cell's physics as ranges (conventions §8): one fieldset of "lo,hi" inputs shared by
// the Plan, Validation and Catalogue pages; empty inputs keep the service's cell.

const RANGES = ["support_friction", "jaw_friction", "part_mass_kg", "grip_force_n"];
const LENGTHS = ["com_tolerance", "profile_tolerance"];

function span(id, text) {
  const parts = text.split(",").map((x) => x.trim()).filter((x) => x !== "");
  const values = parts.map(Number);
  if (!values.length || values.length > 2 || values.some((v) => !Number.isFinite(v))) {
    throw new Error(`${id.replaceAll("_", " ")}: expected a number or lo,hi`);
  }
  return values.length === 1 ? values[0] : values;
}

// The request's `physics` object (null: the service's cell as it is).
export function physicsRequest() {
  const out = {};
  for (const key of RANGES) {
    const text = document.getElementById(`phys-${key}`).value.trim();
    if (text) out[key] = span(key, text);
  }
  for (const key of LENGTHS) {
    const text = document.getElementById(`phys-${key}`).value.trim();
    if (text) out[key] = Number(text);
  }
  const placement = document.getElementById("phys-placement").value;
  if (placement) out.placement = placement;
  return Object.keys(out).length ? out : null;
}

export function limitsWanted() {
  return document.getElementById("phys-limits").checked;
}

// One line of the ranges a plan was made for (its dead_band object).
export function describePhysics(band) {
  if (!band) return "";
  const r = (k, unit = "") => {
    const [lo, hi] = band[k];
    return lo === hi ? `${lo}${unit}` : `${lo}–${hi}${unit}`;
  };
  return `support μ ${r("support_friction")}, jaw μ ${r("jaw_friction")}, mass ${r("part_mass_kg", " kg")}, ` +
    `force ${r("grip_force_n", " N")}, placement ${band.placement}`;
}
