// Draws a world object (docs/protocol.md "World object") on a canvas: walls, rooms shaded and
// labelled, items as coloured shapes with stack counts, the robot and what it holds; 3-D worlds
// one floor at a time. A plan (a candidate's trace) is drawn as a path with its picks and drops,
// and can be animated step by step.

const COLORS = {
  black: '#222', blue: '#2f6fdf', gray: '#8a8a8a', grey: '#8a8a8a', green: '#2e9d48',
  orange: '#f08a24', pink: '#ec6fb0', purple: '#8a4fcf', red: '#d93b3b', yellow: '#f2c81f',
};
const ROOM_TINTS = ['#e8f1ff', '#fff1df', '#e9f8ea', '#f7e8fb', '#fffbd8', '#e4f6f6', '#fde8e8', '#eef0f3', '#f0ecdf'];

export const itemColor = (c) => COLORS[c] || '#555';

// Cells of a world, whatever the dimension: walls as [x,y] or [x,y,z] points or 3-D boxes.
export function worldGeometry(world) {
  const dims = world.bounds?.min?.length === 3 || world.robot?.z !== undefined ? 3 : 2;
  const key = (x, y, z) => (dims === 3 ? `${x},${y},${z}` : `${x},${y}`);
  const walls = new Set();
  for (const w of world.walls || []) walls.add(key(w[0], w[1], w[2] ?? 0));
  for (const b of world.boxes || [])
    for (let x = b.min[0]; x <= b.max[0]; x++)
      for (let y = b.min[1]; y <= b.max[1]; y++)
        for (let z = b.min[2]; z <= b.max[2]; z++) walls.add(key(x, y, z));
  let min = world.bounds?.min, max = world.bounds?.max;
  if (!min || !max) {
    const pts = [...(world.walls || []), ...(world.items || []).map((i) => [i.x, i.y, i.z ?? 0]),
      [world.robot.x, world.robot.y, world.robot.z ?? 0]];
    for (const cells of Object.values(world.rooms || {})) pts.push(...cells);
    min = [0, 1, 2].map((d) => Math.min(...pts.map((p) => p[d] ?? 0)));
    max = [0, 1, 2].map((d) => Math.max(...pts.map((p) => p[d] ?? 0)));
  }
  const floors = [];
  if (dims === 3) for (let z = min[2]; z <= max[2]; z++) floors.push(z);
  return { dims, key, walls, min, max, floors };
}

function roomColor(name, index) {
  return ROOM_TINTS[index % ROOM_TINTS.length];
}

function drawShape(ctx, shape, color, cx, cy, r) {
  ctx.fillStyle = itemColor(color);
  ctx.strokeStyle = 'rgba(0,0,0,0.55)';
  ctx.lineWidth = Math.max(1, r / 7);
  ctx.beginPath();
  if (shape === 'circle') ctx.arc(cx, cy, r, 0, 2 * Math.PI);
  else if (shape === 'triangle') {
    ctx.moveTo(cx, cy - r);
    ctx.lineTo(cx + r * 0.95, cy + r * 0.75);
    ctx.lineTo(cx - r * 0.95, cy + r * 0.75);
    ctx.closePath();
  } else ctx.rect(cx - r * 0.85, cy - r * 0.85, r * 1.7, r * 1.7);
  ctx.fill();
  ctx.stroke();
}

export { drawShape };

export class MapView {
  constructor(canvas) {
    this.canvas = canvas;
    this.ctx = canvas.getContext('2d');
    this.floor = 0;
    this.world = null;
    this.plan = null; // {trace, upTo, end}
  }

  setWorld(world) {
    this.world = world;
    this.geo = world ? worldGeometry(world) : null;
    if (this.geo?.dims === 3 && !this.geo.floors.includes(this.floor)) this.floor = world.robot.z ?? 0;
  }

  // Grid layout: cell size from the canvas size; y grows upwards.
  layout() {
    const { min, max } = this.geo;
    const w = max[0] - min[0] + 1, h = max[1] - min[1] + 1;
    const dpr = window.devicePixelRatio || 1;
    const cssW = this.canvas.clientWidth || this.canvas.width;
    const cell = Math.max(8, Math.floor(Math.min(cssW / w, 640 / h)));
    const W = cell * w, H = cell * h;
    if (this.canvas.width !== Math.round(W * dpr) || this.canvas.height !== Math.round(H * dpr)) {
      this.canvas.width = Math.round(W * dpr);
      this.canvas.height = Math.round(H * dpr);
      this.canvas.style.height = `${H}px`;
    }
    this.ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    return { cell, W, H, px: (x) => (x - min[0]) * cell, py: (y) => (max[1] - y) * cell };
  }

  onFloor(p) {
    return this.geo.dims !== 3 || (p[2] ?? p.z ?? 0) === this.floor;
  }

  draw(world = this.world, plan = null) {
    if (!world) return;
    if (!this.geo) this.setWorld(world);
    const ctx = this.ctx;
    const L = this.layout();
    const { cell } = L;
    const { min, max, walls, key } = this.geo;
    ctx.clearRect(0, 0, L.W, L.H);
    ctx.fillStyle = '#fbfbf8';
    ctx.fillRect(0, 0, L.W, L.H);
    // Rooms: shaded, outlined, labelled at their centre.
    const rooms = Object.entries(world.rooms || {});
    rooms.forEach(([name, cells], i) => {
      const mine = cells.filter((c) => this.onFloor(c));
      if (!mine.length) return;
      ctx.fillStyle = roomColor(name, i);
      for (const c of mine) ctx.fillRect(L.px(c[0]), L.py(c[1]), cell, cell);
    });
    // Grid lines.
    ctx.strokeStyle = 'rgba(0,0,0,0.07)';
    ctx.lineWidth = 1;
    for (let x = min[0]; x <= max[0] + 1; x++) {
      ctx.beginPath(); ctx.moveTo(L.px(x), 0); ctx.lineTo(L.px(x), L.H); ctx.stroke();
    }
    for (let y = min[1] - 1; y <= max[1]; y++) {
      ctx.beginPath(); ctx.moveTo(0, L.py(y)); ctx.lineTo(L.W, L.py(y)); ctx.stroke();
    }
    // Walls.
    ctx.fillStyle = '#3d4048';
    for (let x = min[0]; x <= max[0]; x++)
      for (let y = min[1]; y <= max[1]; y++)
        if (walls.has(key(x, y, this.floor))) ctx.fillRect(L.px(x), L.py(y), cell, cell);
    // Room labels on top of the shading.
    ctx.font = `600 ${Math.max(10, cell * 0.36)}px system-ui, sans-serif`;
    ctx.textAlign = 'center';
    ctx.textBaseline = 'middle';
    rooms.forEach(([name, cells]) => {
      const mine = cells.filter((c) => this.onFloor(c));
      if (!mine.length) return;
      const cx = mine.reduce((s, c) => s + c[0], 0) / mine.length;
      const cy = mine.reduce((s, c) => s + c[1], 0) / mine.length;
      ctx.fillStyle = 'rgba(40,50,80,0.45)';
      ctx.fillText(name, L.px(cx) + cell / 2, L.py(cy) + cell / 2);
    });
    if (plan) this.drawPlan(L, plan);
    this.drawItems(L, world);
    this.drawRobot(L, plan?.robot ?? world.robot);
  }

  drawItems(L, world) {
    const { cell } = L;
    const stacks = new Map();
    for (const it of world.items || []) {
      if (!this.onFloor([it.x, it.y, it.z ?? 0])) continue;
      const k = `${it.x},${it.y}`;
      if (!stacks.has(k)) stacks.set(k, []);
      stacks.get(k).push(it);
    }
    for (const stack of stacks.values()) {
      const { x, y } = stack[0];
      const n = stack.length;
      const r = cell * (n === 1 ? 0.28 : 0.17);
      const slots = [[0.5, 0.5]];
      if (n > 1) slots.splice(0, 1, [0.3, 0.3], [0.7, 0.3], [0.3, 0.7], [0.7, 0.7]);
      stack.slice(0, slots.length).forEach((it, i) =>
        drawShape(this.ctx, it.shape, it.color, L.px(x) + slots[i][0] * cell, L.py(y) + slots[i][1] * cell, r));
      if (n > 1) {
        const ctx = this.ctx;
        const bx = L.px(x) + cell * 0.82, by = L.py(y) + cell * 0.16;
        ctx.fillStyle = '#1d2740';
        ctx.beginPath(); ctx.arc(bx, by, cell * 0.17, 0, 2 * Math.PI); ctx.fill();
        ctx.fillStyle = '#fff';
        ctx.font = `700 ${Math.max(9, cell * 0.22)}px system-ui, sans-serif`;
        ctx.fillText(String(n), bx, by + 0.5);
      }
    }
  }

  drawRobot(L, robot) {
    if (!robot || !this.onFloor([robot.x, robot.y, robot.z ?? 0])) return;
    const ctx = this.ctx, { cell } = L;
    const x = L.px(robot.x), y = L.py(robot.y), m = cell * 0.12;
    ctx.fillStyle = '#1d2740';
    ctx.strokeStyle = '#fff';
    ctx.lineWidth = 2;
    ctx.beginPath();
    ctx.roundRect(x + m, y + m, cell - 2 * m, cell - 2 * m, cell * 0.18);
    ctx.fill();
    ctx.stroke();
    ctx.fillStyle = '#7fe3ff';
    ctx.beginPath(); ctx.arc(x + cell * 0.36, y + cell * 0.4, cell * 0.07, 0, 2 * Math.PI); ctx.fill();
    ctx.beginPath(); ctx.arc(x + cell * 0.64, y + cell * 0.4, cell * 0.07, 0, 2 * Math.PI); ctx.fill();
    const held = robot.holding || [];
    held.slice(0, 3).forEach((it, i) =>
      drawShape(ctx, it.shape, it.color, x + cell * (0.3 + 0.2 * i), y + cell * 0.7, cell * 0.09));
  }

  drawPlan(L, plan) {
    this.ctx.save(); // line styles stay with the plan
    this.drawPlanLines(L, plan);
    this.ctx.restore();
  }

  drawPlanLines(L, plan) {
    const ctx = this.ctx, { cell } = L;
    const steps = plan.trace.slice(0, plan.upTo);
    const start = plan.start;
    const centre = (p) => [L.px(p[0]) + cell / 2, L.py(p[1]) + cell / 2];
    ctx.lineWidth = Math.max(2, cell * 0.12);
    ctx.lineCap = 'round';
    ctx.lineJoin = 'round';
    ctx.strokeStyle = plan.ok ? 'rgba(232,110,20,0.85)' : 'rgba(200,30,30,0.85)';
    let prev = start;
    for (const s of steps) {
      if (s.act !== 'move') continue;
      if (this.onFloor(prev) && this.onFloor(s.to)) {
        const [ax, ay] = centre(prev), [bx, by] = centre(s.to);
        ctx.beginPath(); ctx.moveTo(ax, ay); ctx.lineTo(bx, by); ctx.stroke();
      }
      prev = s.to;
    }
    // Picks and drops: a ring with ↑ (pick) or ↓ (drop).
    for (const s of steps) {
      if (s.act === 'move' || !this.onFloor(s.at)) continue;
      const [cx, cy] = centre(s.at);
      ctx.strokeStyle = s.act === 'pick' ? '#0a7d32' : '#7b2fbf';
      ctx.lineWidth = Math.max(2, cell * 0.08);
      ctx.beginPath(); ctx.arc(cx, cy, cell * 0.45, 0, 2 * Math.PI); ctx.stroke();
    }
  }

  // Animates a plan: the robot walks the trace, picks and drops as it goes, then the end world
  // is shown with the whole path. Calls done() at the end. Returns a cancel function.
  animate(start, trace, end, ok, done) {
    let cancelled = false;
    const startPos = [start.robot.x, start.robot.y, start.robot.z ?? 0];
    const perStep = Math.max(25, Math.min(120, 2500 / Math.max(1, trace.length)));
    let i = 0;
    const robot = { ...start.robot, holding: [...(start.robot.holding || [])] };
    let items = [...(start.items || [])];
    // The plan starts on the robot's floor, whichever floor was being looked at.
    if (this.geo?.dims === 3 && robot.z !== undefined && robot.z !== this.floor) {
      this.floor = robot.z;
      this.onFloorChange?.(this.floor);
    }
    const frame = () => {
      if (cancelled) return;
      if (i >= trace.length) {
        this.draw(end, { trace, upTo: trace.length, start: startPos, ok });
        done?.();
        return;
      }
      const s = trace[i++];
      if (s.act === 'move') {
        [robot.x, robot.y] = s.to;
        if (s.to.length === 3) robot.z = s.to[2];
        if (this.geo.dims === 3 && robot.z !== undefined && robot.z !== this.floor) {
          this.floor = robot.z;
          this.onFloorChange?.(this.floor);
        }
      } else if (s.act === 'pick') {
        const at = items.findIndex((it) => it.x === s.at[0] && it.y === s.at[1] &&
          it.color === s.item.color && it.shape === s.item.shape);
        if (at >= 0) items.splice(at, 1);
        robot.holding.push(s.item);
      } else if (s.act === 'drop') {
        const at = robot.holding.findIndex((it) => it.color === s.item.color && it.shape === s.item.shape);
        if (at >= 0) robot.holding.splice(at, 1);
        items.push({ ...s.item, x: s.at[0], y: s.at[1], z: s.at[2] });
      }
      this.draw({ ...start, items }, { trace, upTo: i, start: startPos, ok, robot });
      setTimeout(() => requestAnimationFrame(frame), perStep);
    };
    requestAnimationFrame(frame);
    return () => { cancelled = true; };
  }
}
