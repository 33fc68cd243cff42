// Protocol conformance with @foxglove/ws-protocol's client (the one Lichtblick uses), during a
// simulator run: connect, subscribe, receive, set a parameter, pause, step, resume.
"use strict";
const { check, fail, tempDir, startHost, exited, until, connect, hostPath, requireClient } = require("./lib");

async function main() {
  requireClient();
  const plugslam = hostPath();
  const out = tempDir("protocol");
  // Paced (the whole simulated run is 169 s of data, under 2 s unpaced): a pause sent while it
  // runs must find it running even when a loaded machine delays this client by a second or more.
  const host = await startHost(plugslam, ["run", "--serve", "127.0.0.1:0", "--paused", "--rate", "20", "-o", out]);
  const s = connect(host.url);
  await until(() => s.serverInfo && s.channels.size > 0 && s.services.size > 0, "serverInfo, advertise, advertiseServices");
  check(s.serverInfo.capabilities.includes("parameters") && s.serverInfo.capabilities.includes("services"),
        "serverInfo offers parameters and services");
  s.subscribeAll();

  // Parameters: all of them by pipeline path, then one set live and read back.
  s.client.getParameters([], "all");
  await until(() => s.parameterValues.some((p) => p.id === "all"), "parameterValues");
  const all = s.parameterValues.find((p) => p.id === "all").parameters;
  const name = "pipeline.tracker.aligner.slices[0].max_distance";
  check(all.length > 50 && all.some((p) => p.name === name), `getParameters lists ${all.length} parameters by path`);
  s.client.setParameters([{ name, value: 0.4 }], "set");
  await until(() => s.parameterValues.some((p) => p.id === "set"), "the reply to setParameters");
  const set = s.parameterValues.find((p) => p.id === "set").parameters.find((p) => p.name === name);
  check(set && Math.abs(set.value - 0.4) < 1e-12, `setParameters ${name} = 0.4 took effect (${set && set.value})`);
  // The same checks as --set: a value out of its range is refused and the value stays.
  s.client.setParameters([{ name, value: -3 }], "bad");
  await until(() => s.parameterValues.some((p) => p.id === "bad"), "the reply to a bad setParameters");
  const kept = s.parameterValues.find((p) => p.id === "bad").parameters.find((p) => p.name === name);
  check(kept && kept.value === 0.4 && s.statuses.some((x) => x.level === 2 && x.id === "bad"),
        "an out-of-range value is refused with an error status and the value kept");

  // Services: step while paused, pause while paused is refused, resume, pause, step again.
  let r = await s.call("step", { count: 5 });
  check(r.ok && /paused at frame 5$/.test(r.data.message), `step 5 from the start: "${r.data && r.data.message}"`);
  r = await s.call("pause");
  check(!r.ok, `pause while paused is refused: "${r.message}"`);
  r = await s.call("resume");
  check(r.ok, `resume: "${r.ok ? r.data.message : r.message}"`);
  await until(() => (s.messages.get("/scan/front") || []).length >= 3, "scans while running");
  r = await s.call("pause");
  check(r.ok && /paused at frame \d+/.test(r.data.message), `pause: "${r.ok ? r.data.message : r.message}"`);
  const at = Number(/frame (\d+)/.exec(r.data.message)[1]);
  r = await s.call("step", { count: 3 });
  check(r.ok && r.data.message === `paused at frame ${at + 3}`, `step 3: "${r.ok ? r.data.message : r.message}"`);
  r = await s.call("step", { count: 0 });
  check(!r.ok, `a malformed step is refused: "${r.message}"`);

  const before = (s.messages.get("/status") || []).length;
  r = await s.call("resume");
  check(r.ok, "resume to the end");
  const code = await exited(host.child);
  check(code === 0, `the run ended normally (exit ${code})`);
  for (const topic of ["/status", "/pose", "/tf", "/tf/maps", "/trajectory", "/scan/front", "/map/front", "/graph"])
    check((s.messages.get(topic) || []).length > 0, `received ${topic} (${(s.messages.get(topic) || []).length})`);
  check((s.messages.get("/status") || []).length > before, "status went on after resume");
  const last = s.messages.get("/status").slice(-1)[0];
  check(last.state === "finished" || last.frame > at, `the last status says ${last.state} at frame ${last.frame}`);
  check(s.errors.length === 0, `no client errors ${s.errors.slice(0, 3).join("; ")}`);
  s.client.close();
}

main().catch((e) => fail(e.stack || e));
