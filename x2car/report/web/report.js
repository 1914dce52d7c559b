// x2car's report page: draws the data the report embeds (x2car/report/report.hpp) with Apache
// ECharts. One section per sensor: the result card, the evidence as the paper plots it (heading
// curves, Fig. 8a; per-segment estimates, Fig. 7; the radar's Doppler cosine, Fig. 9), the camera's
// frames and an adjustment view whose sliders move the projected horizon. Every series the
// calibrator kept is drawn somewhere: those without a chart of their own under "All series".
// window.x2carReport exposes the charts and views to the browser test (x2car/report/web/test).
(function () {
  'use strict';

  const data = JSON.parse(document.getElementById('x2car-data').textContent);
  const root = document.getElementById('x2car-report');
  const charts = [];
  const cameraViews = [];
  window.x2carReport = { data: data, charts: charts, cameraViews: cameraViews };

  const DEG = 180 / Math.PI;
  const COLORS = { ok: '#1a7f37', insufficient_data: '#b35900', unreliable: '#c62828' };

  // ---- small helpers ---------------------------------------------------------------------------

  function el(tag, attributes, ...children) {
    const node = document.createElement(tag);
    for (const [key, value] of Object.entries(attributes || {})) {
      if (key === 'class') node.className = value;
      else if (key === 'text') node.textContent = value;
      else node.setAttribute(key, value);
    }
    for (const child of children) {
      if (child === null || child === undefined) continue;
      node.append(child instanceof Node ? child : document.createTextNode(String(child)));
    }
    return node;
  }

  function number(value, digits) {
    return value === null || value === undefined ? '—' : Number(value).toFixed(digits);
  }

  function signed(value, digits) {
    if (value === null || value === undefined) return '—';
    return (value >= 0 ? '+' : '') + Number(value).toFixed(digits);
  }

  function wrapDegrees(value) {
    let wrapped = value % 360;
    if (wrapped > 180) wrapped -= 360;
    if (wrapped <= -180) wrapped += 360;
    return wrapped;
  }

  function findSeries(result, name) {
    return (result.series || []).find((series) => series.name === name) || null;
  }

  // A series' values in the unit a person reads: radians as degrees.
  function readable(series) {
    const factor = series.unit === 'rad' ? DEG : 1;
    return series.value.map((value) => (value === null ? null : value * factor));
  }

  function readableUnit(series) {
    return series.unit === 'rad' ? 'deg' : series.unit;
  }

  // Angles as one continuous curve (headings jump at ±180 deg otherwise).
  function unwrapped(values) {
    const out = [];
    let offset = 0;
    let previous = null;
    for (const value of values) {
      if (value === null) {
        out.push(null);
        continue;
      }
      if (previous !== null) {
        const step = value + offset - previous;
        if (step > 180) offset -= 360;
        if (step < -180) offset += 360;
      }
      previous = value + offset;
      out.push(previous);
    }
    return out;
  }

  function pairs(xs, ys) {
    const out = [];
    for (let i = 0; i < ys.length; ++i) out.push([xs[i], ys[i]]);
    return out;
  }

  function timeOf(series) {
    return series.time.length ? series.time : series.value.map((_, i) => i);
  }

  // Runs of a 0/1 series as [start, end] time spans (the camera's steady windows).
  function runsOf(series) {
    const spans = [];
    let start = null;
    const time = timeOf(series);
    for (let i = 0; i < series.value.length; ++i) {
      const on = series.value[i] > 0.5;
      if (on && start === null) start = time[i];
      if (!on && start !== null) {
        spans.push([start, time[i - 1]]);
        start = null;
      }
    }
    if (start !== null) spans.push([start, time[time.length - 1]]);
    return spans;
  }

  // Times on the Unix clock (KITTI, the simulator's camera) shown from the log's start.
  function shiftTimes(sensor) {
    const firsts = (sensor.result.series || []).filter((s) => s.time.length).map((s) => s.time[0]);
    const origin = firsts.length ? Math.min(...firsts) : 0;
    sensor.timeLabel = 'time [s]';
    if (!(origin > 1e5)) return;
    sensor.timeLabel = 'time [s] from ' + new Date(origin * 1000).toISOString().replace('.000Z', 'Z');
    for (const series of sensor.result.series) {
      series.time = series.time.map((t) => (t === null ? null : t - origin));
    }
    for (const frame of sensor.frames || []) frame.time_s -= origin;
    if (sensor.evaluation) {
      for (const segment of sensor.evaluation.segments) {
        segment.start_s -= origin;
        segment.end_s -= origin;
      }
    }
  }

  // An axis range that holds the central 96 % of the values and the estimate, so that a few wild
  // samples (a car standing, a turn) do not flatten the rest; zoom and restore show everything.
  function robustRange(valueLists, estimate) {
    const values = [].concat(...valueLists).filter((v) => v !== null && Number.isFinite(v));
    if (values.length < 20) return {};
    values.sort((a, b) => a - b);
    let low = values[Math.floor(0.02 * (values.length - 1))];
    let high = values[Math.ceil(0.98 * (values.length - 1))];
    if (estimate !== null && estimate !== undefined) {
      low = Math.min(low, estimate);
      high = Math.max(high, estimate);
    }
    const pad = Math.max(0.15 * (high - low), 1e-3 * Math.max(1, Math.abs(high)));
    const round = (v) => Number(v.toPrecision(4));
    return { min: round(low - pad), max: round(high + pad) };
  }

  // ---- charts ----------------------------------------------------------------------------------

  // One ECharts chart in `parent`, with zoom (drag, wheel, slider), hover tooltips and a toolbox.
  function chart(parent, title, option, options) {
    const settings = options || {};
    const box = el('div', { class: 'chart-box' });
    const div = el('div', { class: 'chart', 'data-title': title });
    div.style.height = (settings.height || 320) + 'px';
    box.append(el('h4', { text: title }), div);
    if (settings.note) box.append(el('p', { class: 'note', text: settings.note }));
    parent.append(box);
    const instance = echarts.init(div, null, { renderer: 'canvas' });
    const base = {
      animation: false,
      grid: { left: 70, right: 30, top: 40, bottom: 70 },
      tooltip: { trigger: settings.scatter ? 'item' : 'axis', confine: true },
      legend: { top: 5, type: 'scroll' },
      toolbox: {
        right: 10,
        feature: { dataZoom: {}, restore: {}, saveAsImage: { title: 'PNG' } },
      },
      dataZoom: settings.noZoom ? [] : [
        { type: 'inside', xAxisIndex: 0, filterMode: 'none' },
        { type: 'slider', xAxisIndex: 0, height: 18, bottom: 10, filterMode: 'none' },
      ],
    };
    instance.setOption(Object.assign(base, option));
    // The page's grid settles as boxes are added after this one: follow the box's size.
    new ResizeObserver(() => instance.resize()).observe(div);
    charts.push({ title: title, instance: instance, element: div });
    return instance;
  }

  let currentTimeLabel = 'time [s]';

  function timeAxis() {
    return { type: 'value', name: currentTimeLabel, nameLocation: 'middle', nameGap: 25,
             scale: true };
  }

  function valueAxis(name, range) {
    const axis = { type: 'value', name: name, scale: true, nameTextStyle: { align: 'left' } };
    // A set range's ends are not round numbers: label the round steps only.
    if (range && range.min !== undefined) axis.axisLabel = { showMinLabel: false, showMaxLabel: false };
    return Object.assign(axis, range || {});
  }

  function line(name, points, extra) {
    return Object.assign({ name: name, type: 'line', data: points, showSymbol: false,
                           sampling: 'lttb', connectNulls: false, lineStyle: { width: 1.2 } },
                         extra || {});
  }

  function scatter(name, points, extra) {
    return Object.assign({ name: name, type: 'scatter', data: points, symbolSize: 4 },
                         extra || {});
  }

  function estimateLine(label, value) {
    if (value === null || value === undefined) return undefined;
    return {
      silent: true, symbol: 'none',
      lineStyle: { color: '#c62828', type: 'dashed' },
      label: { formatter: label + ' ' + Number(value).toFixed(3), position: 'insideEndTop' },
      data: [{ yAxis: value }],
    };
  }

  // ---- the page --------------------------------------------------------------------------------

  function statusBadge(status) {
    const badge = el('span', { class: 'badge', text: status.replace('_', ' ') });
    badge.style.background = COLORS[status] || '#555';
    return badge;
  }

  function angleError(result, truth, key) {
    if (!truth || result[key + '_deg'] === null || result[key + '_deg'] === undefined) return null;
    return wrapDegrees(result[key + '_deg'] - truth[key + '_deg']);
  }

  function summaryTable() {
    const anyTruth = data.sensors.some((sensor) => sensor.truth);
    const head = ['sensor', 'status', 'method', 'roll [deg]', 'pitch [deg]', 'yaw [deg]',
                  'z [m]'];
    if (anyTruth) head.push('error vs truth [deg]');
    const table = el('table', { class: 'summary' });
    table.append(el('tr', {}, ...head.map((text) => el('th', { text: text }))));
    for (const sensor of data.sensors) {
      const r = sensor.result;
      const std = r.std_deg || {};
      const cell = (key) => r[key + '_deg'] === null ? 'not observed'
          : number(r[key + '_deg'], 3) + ' ± ' + number(std[key], 3);
      const row = el('tr', {},
        el('td', {}, el('a', { href: '#sensor-' + sensor.name, text: sensor.name })),
        el('td', {}, statusBadge(r.status)),
        el('td', { text: r.method || '—' }),
        el('td', { text: cell('roll') }), el('td', { text: cell('pitch') }),
        el('td', { text: cell('yaw') }),
        el('td', { text: r.z_m === null ? '—' : number(r.z_m, 3) + ' ± ' + number((r.std_m || {}).z, 3) }));
      if (anyTruth) {
        const errors = ['roll', 'pitch', 'yaw'].map((key) => angleError(r, sensor.truth, key))
          .map((value) => signed(value, 3));
        row.append(el('td', { text: sensor.truth ? errors.join(' / ') : 'no truth' }));
      }
      table.append(row);
    }
    return table;
  }

  function countsTable(title, counts) {
    // Reasons that left nothing out are noise in a table of what was left out.
    const entries = Object.entries(counts || {}).filter(([, count]) => count !== 0);
    if (!entries.length) return null;
    const table = el('table', { class: 'counts' });
    table.append(el('tr', {}, el('th', { colspan: 2, text: title })));
    for (const [name, count] of entries) {
      table.append(el('tr', {}, el('td', { text: name.replace(/_/g, ' ') }),
                      el('td', { class: 'num', text: count })));
    }
    return table;
  }

  function resultCard(sensor) {
    const r = sensor.result;
    const card = el('div', { class: 'card' });
    card.append(el('div', { class: 'card-head' }, statusBadge(r.status),
                   el('span', { class: 'method', text: 'method: ' + (r.method || '—') }),
                   r.seconds !== undefined ? el('span', { class: 'method',
                     text: 'took ' + number(r.seconds, 2) + ' s' }) : null));
    if (r.reason) card.append(el('p', { class: 'reason', text: r.reason }));
    const table = el('table', { class: 'angles' });
    const head = ['', 'estimate', '± standard error'];
    if (sensor.truth) head.push('truth', 'error');
    table.append(el('tr', {}, ...head.map((text) => el('th', { text: text }))));
    for (const key of ['roll', 'pitch', 'yaw']) {
      const value = r[key + '_deg'];
      const row = el('tr', {}, el('td', { text: key + ' [deg]' }),
                     el('td', { class: 'num', text: value === null ? 'not observable' : number(value, 4) }),
                     el('td', { class: 'num', text: number((r.std_deg || {})[key], 4) }));
      if (sensor.truth) {
        row.append(el('td', { class: 'num', text: number(sensor.truth[key + '_deg'], 4) }),
                   el('td', { class: 'num', text: signed(angleError(r, sensor.truth, key), 4) }));
      }
      table.append(row);
    }
    if (r.z_m !== null && r.z_m !== undefined) {
      const row = el('tr', {}, el('td', { text: 'z [m]' }), el('td', { class: 'num', text: number(r.z_m, 4) }),
                     el('td', { class: 'num', text: number((r.std_m || {}).z, 4) }));
      if (sensor.truth) {
        row.append(el('td', { class: 'num', text: number(sensor.truth.z_m, 4) }),
                   el('td', { class: 'num', text: signed(r.z_m - sensor.truth.z_m, 4) }));
      }
      table.append(row);
    }
    card.append(table);
    const counts = el('div', { class: 'counts-row' });
    for (const node of [countsTable('support', r.support),
                        countsTable('rejected, by reason', r.rejections)]) {
      if (node) counts.append(node);
    }
    card.append(counts);
    const diagnostics = Object.entries(r.diagnostics || {});
    if (diagnostics.length) {
      const details = el('details', {}, el('summary', { text: 'diagnostics (' + diagnostics.length + ')' }));
      const table = el('table', { class: 'counts' });
      for (const [name, value] of diagnostics) {
        table.append(el('tr', {}, el('td', { text: name }),
                        el('td', { class: 'num', text: Number(value).toPrecision(6) })));
      }
      details.append(table);
      card.append(details);
    }
    return card;
  }

  // ---- evidence charts, each returning the series names it drew ----------------------------------

  // The paper's Fig. 8a: the vehicle's heading from its track and the sensor's heading, with the
  // straight stretches that gave the yaw shaded.
  function headingCharts(parent, sensor) {
    const r = sensor.result;
    const vehicle = findSeries(r, 'track_heading');
    const device = findSeries(r, 'sensor_heading');
    const speed = findSeries(r, 'speed');
    // The track's heading and the offset are noise while the car stands: left out below 0.5 m/s.
    const moving = (series) => {
      const values = readable(series);
      if (!speed || speed.value.length !== values.length) return values;
      return values.map((v, i) => (speed.value[i] !== null && speed.value[i] >= 0.5 ? v : null));
    };
    const drawn = [];
    if (vehicle && device) {
      const spans = [];
      const starts = findSeries(r, 'segment_start_time');
      if (starts) {
        starts.value.forEach((start, i) => spans.push([{ xAxis: start },
                                                        { xAxis: 2 * starts.time[i] - start }]));
      }
      chart(parent, 'Heading: vehicle (track) and sensor', {
        xAxis: timeAxis(), yAxis: valueAxis('heading [deg]'),
        series: [
          line('vehicle heading', pairs(vehicle.time, unwrapped(moving(vehicle))),
               { markArea: spans.length ? { silent: true, itemStyle: { color: 'rgba(26,127,55,0.10)' },
                                             data: spans } : undefined }),
          line('sensor heading', pairs(device.time, unwrapped(readable(device)))),
        ],
      }, { note: 'Shaded: the straight stretches whose heading offset gave the yaw (the paper\'s Fig. 8a). ' +
           'The vehicle\'s heading is left out where it was slower than 0.5 m/s.' });
      drawn.push('track_heading', 'sensor_heading', 'segment_start_time');
    }
    const offset = findSeries(r, 'heading_offset');
    if (offset) {
      const offsetValues = moving(offset);
      const series = [line('per-sample offset', pairs(offset.time, offsetValues),
                           { markLine: estimateLine('yaw', r.yaw_deg) })];
      const segmentYaw = findSeries(r, 'segment_yaw');
      if (segmentYaw) {
        series.push(scatter('straight segment', pairs(segmentYaw.time, readable(segmentYaw)),
                            { symbolSize: 7 }));
        drawn.push('segment_yaw');
      }
      chart(parent, 'Sensor heading − vehicle heading over time', {
        xAxis: timeAxis(), yAxis: valueAxis('offset [deg]', robustRange([offsetValues], r.yaw_deg)),
        series: series,
      });
      drawn.push('heading_offset');
    }
    const pitch = findSeries(r, 'velocity_pitch');
    if (pitch && r.sensor === 'ins') {
      const pitchValues = moving(pitch);
      const series = [line('per-sample pitch', pairs(pitch.time, pitchValues),
                           { markLine: estimateLine('pitch', r.pitch_deg) })];
      const segmentPitch = findSeries(r, 'segment_pitch');
      if (segmentPitch) {
        series.push(scatter('straight segment', pairs(segmentPitch.time, readable(segmentPitch)),
                            { symbolSize: 7 }));
        drawn.push('segment_pitch');
      }
      chart(parent, 'Pitch of the velocity in the sensor frame', {
        xAxis: timeAxis(), yAxis: valueAxis('pitch [deg]', robustRange([pitchValues], r.pitch_deg)),
        series: series,
      });
      drawn.push('velocity_pitch');
    }
    return drawn;
  }

  function lidarCharts(parent, sensor) {
    const r = sensor.result;
    const roll = findSeries(r, 'ground_roll');
    const pitch = findSeries(r, 'ground_pitch');
    const height = findSeries(r, 'ground_height');
    const drawn = [];
    if (roll && pitch) {
      chart(parent, 'Ground plane per frame: roll and pitch', {
        xAxis: timeAxis(), yAxis: valueAxis('[deg]', robustRange([readable(roll), readable(pitch)])),
        series: [line('roll', pairs(roll.time, readable(roll)), { markLine: estimateLine('roll', r.roll_deg) }),
                 line('pitch', pairs(pitch.time, readable(pitch)), { markLine: estimateLine('pitch', r.pitch_deg) })],
      });
      drawn.push('ground_roll', 'ground_pitch');
    }
    if (height) {
      chart(parent, 'Ground plane per frame: height of the LiDAR above the road', {
        xAxis: timeAxis(), yAxis: valueAxis('[m]', robustRange([height.value], r.z_m)),
        series: [line('height', pairs(height.time, readable(height)), { markLine: estimateLine('z', r.z_m) })],
      });
      drawn.push('ground_height');
    }
    const east = findSeries(r, 'odometry_x');
    const north = findSeries(r, 'odometry_y');
    if (east && north) {
      // A map: one metre as long on both axes (equal spans on a square plot).
      const finite = (values) => values.filter((v) => v !== null);
      const xs = finite(east.value);
      const ys = finite(north.value);
      const span = Math.max(Math.max(...xs) - Math.min(...xs), Math.max(...ys) - Math.min(...ys), 1) * 1.1;
      const centre = (values) => (Math.max(...values) + Math.min(...values)) / 2;
      const axis = (name, values) => ({
        type: 'value', name: name, nameLocation: 'middle', nameGap: 25,
        min: Number((centre(values) - span / 2).toFixed(1)), max: Number((centre(values) + span / 2).toFixed(1)),
        axisLabel: { showMinLabel: false, showMaxLabel: false },
      });
      const width = parent.clientWidth > 0 ? Math.min(parent.clientWidth, 640) : 560;
      chart(parent, 'LiDAR odometry path (map)', {
        grid: { left: 70, right: 30, top: 40, bottom: 70 },
        xAxis: axis('x [m]', xs), yAxis: axis('y [m]', ys),
        tooltip: { trigger: 'item' },
        series: [line('path', pairs(east.value, north.value), { showSymbol: false })],
      }, { height: width - 30, noZoom: true,
           note: 'In the first sweep\'s frame, levelled by the estimated roll and pitch.' });
      drawn.push('odometry_x', 'odometry_y');
    }
    return drawn;
  }

  // The paper's Fig. 9: the static detections' v_r / cos(θ) against the car's speed, on the line
  // of the fitted yaw (slope: the speed scale).
  function radarCharts(parent, sensor) {
    const r = sensor.result;
    const drawn = [];
    const ego = findSeries(r, 'doppler_car_speed');
    const projected = findSeries(r, 'doppler_implied_speed');
    if (ego && projected) {
      const points = pairs(ego.value, projected.value).filter((p) => p[0] !== null && p[1] !== null);
      const scale = (r.diagnostics || {}).speed_scale || (r.diagnostics || {}).velocity_speed_scale || 1;
      // The fitted line over the speeds driven (a line from the origin would start off the axis).
      const top = points.reduce((max, p) => Math.max(max, p[0]), 0);
      const bottom = points.reduce((min, p) => Math.min(min, p[0]), top);
      chart(parent, 'Doppler: −v_r / cos(θ + yaw) against the car\'s speed', {
        xAxis: { type: 'value', name: 'car speed at the radar [m/s]', nameLocation: 'middle', nameGap: 25 },
        yAxis: valueAxis('[m/s]', robustRange([points.map((p) => p[1])], null)),
        series: [scatter('static detections', points, { symbolSize: 3, large: true }),
                 line('fit (slope = speed scale ' + scale.toFixed(4) + ')', [[bottom, bottom * scale], [top, top * scale]],
                      { lineStyle: { color: '#c62828', width: 2 } })],
      }, { scatter: true, noZoom: true, note: 'The paper\'s Fig. 9: with the right yaw the static detections lie on ' +
           'one line through the origin. Detections within 60° of square to the motion are left out.' });
      drawn.push('doppler_car_speed', 'doppler_implied_speed');
    }
    const windows = findSeries(r, 'window_yaw');
    if (windows) {
      chart(parent, 'Velocity method: yaw per time window', {
        xAxis: timeAxis(), yAxis: valueAxis('yaw [deg]'),
        series: [scatter('window', pairs(windows.time, readable(windows)),
                         { markLine: estimateLine('yaw', r.yaw_deg), symbolSize: 6 })],
      }, { scatter: true });
      drawn.push('window_yaw');
    }
    const pairsYaw = findSeries(r, 'pair_yaw');
    if (pairsYaw) {
      chart(parent, 'Position method: yaw per object pair', {
        xAxis: timeAxis(), yAxis: valueAxis('yaw [deg]', robustRange([readable(pairsYaw)], r.yaw_deg)),
        series: [scatter('pair', pairs(pairsYaw.time, readable(pairsYaw)),
                         { markLine: estimateLine('yaw', r.yaw_deg) })],
      }, { scatter: true });
      drawn.push('pair_yaw');
    }
    return drawn;
  }

  function cameraCharts(parent, sensor) {
    const r = sensor.result;
    const drawn = [];
    const window = findSeries(r, 'in_window');
    const spans = window ? runsOf(window).map((span) => [{ xAxis: span[0] }, { xAxis: span[1] }]) : [];
    const series = [];
    const shown = [];
    for (const key of ['roll', 'pitch', 'yaw']) {
      const frame = findSeries(r, 'frame_' + key);
      if (!frame) continue;
      shown.push(readable(frame));
      series.push(line(key, pairs(frame.time, readable(frame)), {
        markLine: estimateLine(key, r[key + '_deg']),
        markArea: key === 'roll' && spans.length
          ? { silent: true, itemStyle: { color: 'rgba(26,127,55,0.10)' }, data: spans } : undefined,
      }));
      drawn.push('frame_' + key);
    }
    if (series.length) {
      chart(parent, 'Per-frame angles (shaded: the steady windows that were averaged)', {
        xAxis: timeAxis(), yAxis: valueAxis('[deg]', robustRange(shown)), series: series,
      });
      if (window) drawn.push('in_window');
    }
    const u = findSeries(r, 'road_vanishing_point_u');
    const v = findSeries(r, 'road_vanishing_point_v');
    if (u && v) {
      chart(parent, 'Road vanishing point per frame', {
        xAxis: timeAxis(), yAxis: valueAxis('[px]', robustRange([u.value, v.value])),
        series: [line('u', pairs(u.time, u.value)), line('v', pairs(v.time, v.value))],
      });
      drawn.push('road_vanishing_point_u', 'road_vanishing_point_v');
    }
    return drawn;
  }

  // Every other series, one chart each, folded away.
  function otherCharts(parent, sensor, drawn) {
    const rest = (sensor.result.series || []).filter((series) => !drawn.includes(series.name));
    if (!rest.length) return;
    const details = el('details', { class: 'all-series' },
                       el('summary', { text: 'All series (' + rest.length + ' more)' }));
    parent.append(details);
    // Drawn when first opened: a hidden chart has no size.
    let done = false;
    details.addEventListener('toggle', () => {
      if (done || !details.open) return;
      done = true;
      currentTimeLabel = sensor.timeLabel;
      for (const series of rest) {
        chart(details, series.name + (series.unit ? ' [' + readableUnit(series) + ']' : ''), {
          xAxis: series.time.length ? timeAxis() : { type: 'value', name: 'index' },
          yAxis: valueAxis(readableUnit(series)),
          series: [line(series.name, pairs(timeOf(series), readable(series)))],
        }, { height: 220 });
      }
    });
  }

  // The paper's Fig. 7 and Table III: each segment's estimate, as a box and the points, relative
  // to the whole log's (so the three angles share an axis), straight segments apart.
  function evaluationCharts(parent, sensor) {
    const evaluation = sensor.evaluation;
    if (!evaluation) return;
    const whole = evaluation.whole_log;
    const summary = evaluation.summary;
    parent.append(el('h3', { text: 'Segments (the paper\'s protocol)' }));
    parent.append(el('p', { text: summary.with_estimate + ' of ' + summary.segments +
      ' segments gave an estimate; ' + number(summary.seconds_per_segment, 2) + ' s per segment.' }));
    const table = el('table', { class: 'angles' });
    table.append(el('tr', {}, ...['', 'segments', 'mean', 'std (all)', 'std (straight)']
      .map((text) => el('th', { text: text }))));
    for (const key of ['roll', 'pitch', 'yaw']) {
      const spread = summary[key];
      if (!spread.segments) continue;
      table.append(el('tr', {}, el('td', { text: key + ' [deg]' }),
        el('td', { class: 'num', text: spread.segments + ' (' + spread.straight_segments + ' straight)' }),
        el('td', { class: 'num', text: number(spread.mean_deg, 4) }),
        el('td', { class: 'num', text: number(spread.std_deg, 4) }),
        el('td', { class: 'num', text: number(spread.std_straight_deg, 4) })));
    }
    parent.append(table);
    const keys = ['roll', 'pitch', 'yaw'].filter((key) => summary[key].segments > 0);
    if (!keys.length) return;
    const boxes = [];
    const straight = [];
    const curved = [];
    keys.forEach((key, index) => {
      const reference = whole[key + '_deg'] !== null ? whole[key + '_deg'] : summary[key].mean_deg;
      const values = [];
      for (const segment of evaluation.segments) {
        const value = segment.result[key + '_deg'];
        if (segment.result.status !== 'ok' || value === null) continue;
        const difference = wrapDegrees(value - reference);
        values.push(difference);
        (segment.straight ? straight : curved).push([index, difference, segment.start_s]);
      }
      values.sort((a, b) => a - b);
      const q = (p) => values.length ? values[Math.min(values.length - 1, Math.floor(p * (values.length - 1) + 0.5))] : null;
      boxes.push(values.length ? [values[0], q(0.25), q(0.5), q(0.75), values[values.length - 1]] : []);
    });
    chart(parent, 'Segment estimates minus the whole log\'s', {
      xAxis: { type: 'category', data: keys },
      yAxis: valueAxis('[deg]'),
      tooltip: { trigger: 'item' },
      series: [
        { name: 'spread', type: 'boxplot', data: boxes },
        scatter('straight segment', straight, { symbolSize: 8 }),
        scatter('other segment', curved, { symbolSize: 8, symbol: 'diamond' }),
      ],
    }, { scatter: true, noZoom: true, note: 'The paper\'s Fig. 7: each point is one segment calibrated on its own.' });
    if (sensor.truth) {
      const series = keys.map((key) => line(key, evaluation.segments
        .filter((segment) => segment.result.status === 'ok' && segment.result[key + '_deg'] !== null)
        .map((segment) => [segment.start_s, wrapDegrees(segment.result[key + '_deg'] - sensor.truth[key + '_deg'])]),
        { showSymbol: true }));
      chart(parent, 'Each segment\'s error against the truth', {
        xAxis: timeAxis(), yAxis: valueAxis('error [deg]'), series: series,
      });
    }
  }

  // ---- the camera's frames and adjustment view -------------------------------------------------

  // R = Rz(yaw) Ry(pitch) Rx(roll), angles in radians (docs/conventions.md).
  function rotation(roll, pitch, yaw) {
    const [cr, sr, cp, sp, cy, sy] = [Math.cos(roll), Math.sin(roll), Math.cos(pitch),
                                      Math.sin(pitch), Math.cos(yaw), Math.sin(yaw)];
    return [[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
            [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
            [-sp, cp * sr, cp * cr]];
  }

  function transposeTimes(m, v) {
    return [0, 1, 2].map((i) => m[0][i] * v[0] + m[1][i] * v[1] + m[2][i] * v[2]);
  }

  // A direction of the car (V) in the camera's optical frame: R_O_V = R_B_O^T R_V_B^T, with the
  // optical frame's x right, y down, z forward (R_B_O maps optical (x, y, z) to body (z, -x, -y)).
  function opticalFromVehicle(angles, direction) {
    const body = transposeTimes(rotation(angles.roll / DEG, angles.pitch / DEG, angles.yaw / DEG), direction);
    return [-body[1], -body[2], body[0]];
  }

  function project(frame, ray) {
    if (ray[2] <= 1e-6) return null;
    return [frame.fx * ray[0] / ray[2] + frame.cx, frame.fy * ray[1] / ray[2] + frame.cy];
  }

  // The horizon for `angles`: the image line of the rays perpendicular to the car's up axis.
  function horizonFor(frame, angles) {
    const up = opticalFromVehicle(angles, [0, 0, 1]);
    return [up[0] / frame.fx, up[1] / frame.fy,
            up[2] - up[0] * frame.cx / frame.fx - up[1] * frame.cy / frame.fy];
  }

  // Where the line a u + b v + c = 0 crosses the image's left and right edges.
  function lineEnds(line, width) {
    if (Math.abs(line[1]) < 1e-12) return null;
    const v = (u) => -(line[0] * u + line[2]) / line[1];
    return [[-0.5, v(-0.5)], [width - 0.5, v(width - 0.5)]];
  }

  function loadImage(frame) {
    const image = new Image();
    image.src = 'data:image/jpeg;base64,' + frame.jpeg_base64;
    return image;
  }

  function strokeLine(context, ends, color, width, dash) {
    if (!ends) return;
    context.save();
    context.strokeStyle = color;
    context.lineWidth = width;
    context.setLineDash(dash || []);
    context.beginPath();
    context.moveTo(ends[0][0] + 0.5, ends[0][1] + 0.5);
    context.lineTo(ends[1][0] + 0.5, ends[1][1] + 0.5);
    context.stroke();
    context.restore();
  }

  function cross(context, point, color) {
    if (!point) return;
    context.save();
    context.strokeStyle = color;
    context.lineWidth = 2;
    context.beginPath();
    context.arc(point[0] + 0.5, point[1] + 0.5, 7, 0, 2 * Math.PI);
    context.moveTo(point[0] - 11, point[1]);
    context.lineTo(point[0] + 12, point[1]);
    context.moveTo(point[0], point[1] - 11);
    context.lineTo(point[0], point[1] + 12);
    context.stroke();
    context.restore();
  }

  const ROLE_COLORS = { road: '#00e676', horizon: '#40c4ff', other: 'rgba(255,235,59,0.55)' };

  // A frame as the estimator saw it: its segments by role, the road's vanishing point, the horizon.
  function frameFigure(parent, frame) {
    const figure = el('figure', { class: 'frame' });
    const canvas = el('canvas', { width: frame.width, height: frame.height, class: 'frame-canvas' });
    figure.append(canvas, el('figcaption', { text: frame.name.split('/').pop() + ' — t = ' + number(frame.time_s, 2) + ' s' +
      (frame.rejection ? ' — not usable: ' + frame.rejection.replace(/_/g, ' ') : '') }));
    parent.append(figure);
    const image = loadImage(frame);
    image.onload = () => {
      const context = canvas.getContext('2d');
      context.drawImage(image, 0, 0);
      for (const segment of frame.lines) {
        strokeLine(context, [[segment[0], segment[1]], [segment[2], segment[3]]],
                   ROLE_COLORS[segment[4]] || ROLE_COLORS.other, segment[4] === 'other' ? 1 : 2);
      }
      if (frame.horizon) strokeLine(context, lineEnds(frame.horizon, frame.width), '#40c4ff', 2, [8, 6]);
      cross(context, frame.vanishing_point, '#ff1744');
    };
  }

  function exportTexts(sensor, angles) {
    const rad = (value) => String(Number((value / DEG).toPrecision(12)));
    const name = sensor.name;
    const yaml = 'base_link:\n  ' + name + ':\n    x: 0\n    y: 0\n    z: 0\n    roll: ' + rad(angles.roll) +
      '\n    pitch: ' + rad(angles.pitch) + '\n    yaw: ' + rad(angles.yaw) + '\n';
    const urdf = '<joint name="' + name + '_joint" type="fixed">\n  <parent link="base_link"/>\n  <child link="' +
      name + '"/>\n  <origin xyz="0 0 0" rpy="' + [angles.roll, angles.pitch, angles.yaw].map(rad).join(' ') +
      '"/>\n</joint>\n';
    const json = JSON.stringify({
      sensor: 'camera', status: 'ok', reason: 'adjusted by hand in the x2car report', method: 'manual',
      roll_deg: angles.roll, pitch_deg: angles.pitch, yaw_deg: angles.yaw, z_m: null,
      std_deg: { roll: null, pitch: null, yaw: null }, std_m: { z: null },
      support: {}, rejections: {}, diagnostics: {}, series: [],
    }, null, 2) + '\n';
    return { yaml: yaml, urdf: urdf, json: json };
  }

  // The adjustment view: the car's forward vanishing point, the horizon and lane guides projected
  // with the sliders' angles, live; the translation is not estimated and exported as 0.
  function adjustmentView(parent, sensor) {
    const frame = sensor.frames.find((f) => !f.rejection) || sensor.frames[0];
    const r = sensor.result;
    // The estimate; without one, the per-frame angles' median (a starting point, not a result).
    const median = (key) => {
      const frame = findSeries(r, 'frame_' + key);
      const values = frame ? readable(frame).filter((v) => v !== null).sort((a, b) => a - b) : [];
      return values.length ? values[Math.floor(values.length / 2)] : 0;
    };
    const start = {};
    for (const key of ['roll', 'pitch', 'yaw']) {
      start[key] = r[key + '_deg'] !== null && r[key + '_deg'] !== undefined ? r[key + '_deg'] : median(key);
      start[key] = Number(start[key].toFixed(2));
    }
    const angles = Object.assign({}, start);
    const box = el('div', { class: 'adjust' });
    parent.append(el('h3', { text: 'Adjust by eye' }), box);
    box.append(el('p', { class: 'note', text: 'Move the sliders until the dashed horizon and the lane guides sit on ' +
      'the scene; the red cross is the vanishing point of the car\'s travel (ahead of it, or behind it for a camera ' +
      'that looks back). Export the adjusted mounting below.' +
      (r.status === 'ok' ? '' : ' No estimate: the sliders start at the per-frame angles\' median.') }));
    const canvas = el('canvas', { width: frame.width, height: frame.height, class: 'frame-canvas adjust-canvas' });
    box.append(canvas);
    const controls = el('div', { class: 'sliders' });
    box.append(controls);
    const heightInput = el('input', { type: 'number', value: '1.5', step: '0.05', min: '0.3', max: '5' });
    const laneInput = el('input', { type: 'number', value: '3.5', step: '0.1', min: '2', max: '6' });
    const outputs = el('div', { class: 'exports' });
    const text = el('textarea', { rows: 10, cols: 70, readonly: 'readonly', class: 'export-text' });
    const image = loadImage(frame);
    const view = { sensor: sensor.name, canvas: canvas, angles: angles, horizon: null, sliders: {} };
    cameraViews.push(view);

    function draw() {
      const context = canvas.getContext('2d');
      context.clearRect(0, 0, canvas.width, canvas.height);
      if (image.complete) context.drawImage(image, 0, 0);
      const horizon = horizonFor(frame, angles);
      const ends = lineEnds(horizon, frame.width);
      view.horizon = ends;
      canvas.setAttribute('data-horizon', ends ? ends.flat().map((v) => v.toFixed(2)).join(',') : '');
      strokeLine(context, ends, '#40c4ff', 2, [10, 6]);
      const height = Number(heightInput.value) || 1.5;
      const half = (Number(laneInput.value) || 3.5) / 2;
      // The road ahead of the car and behind it, each where the camera sees it (a camera that looks
      // back, or one that looks sideways and sees both); the cross is the travel's vanishing point
      // on the side the camera faces.
      const along = opticalFromVehicle(angles, [1, 0, 0])[2] >= 0 ? 1 : -1;
      let guidePoints = 0;
      for (const direction of [1, -1]) {
        for (const side of [-3 * half, -half, half, 3 * half]) {
          const points = [];
          for (let x = 3; x <= 120; x *= 1.15) {
            const pixel = project(frame, opticalFromVehicle(angles, [direction * x, side, -height]));
            if (pixel) points.push(pixel);
          }
          guidePoints += points.length;
          context.save();
          context.strokeStyle = Math.abs(side) < half * 2 ? '#ffea00' : 'rgba(255,234,0,0.5)';
          context.lineWidth = 2;
          context.beginPath();
          points.forEach((p, i) => (i ? context.lineTo(p[0], p[1]) : context.moveTo(p[0], p[1])));
          context.stroke();
          context.restore();
        }
      }
      cross(context, project(frame, opticalFromVehicle(angles, [along, 0, 0])), '#ff1744');
      canvas.setAttribute('data-guide-points', String(guidePoints));
    }

    for (const key of ['roll', 'pitch', 'yaw']) {
      const value = el('span', { class: 'slider-value', text: angles[key].toFixed(2) + '°' });
      const slider = el('input', { type: 'range', min: String(start[key] - 5), max: String(start[key] + 5),
                                   step: '0.01', value: String(angles[key]), 'data-angle': key });
      slider.addEventListener('input', () => {
        angles[key] = Number(slider.value);
        value.textContent = angles[key].toFixed(2) + '°';
        draw();
      });
      view.sliders[key] = slider;
      controls.append(el('label', {}, key + ' ', slider, ' ', value));
    }
    controls.append(el('label', {}, 'camera height [m] ', heightInput),
                    el('label', {}, 'lane width [m] ', laneInput));
    heightInput.addEventListener('input', draw);
    laneInput.addEventListener('input', draw);
    const reset = el('button', { type: 'button', text: 'reset to the estimate' });
    reset.addEventListener('click', () => {
      Object.assign(angles, start);
      for (const key of ['roll', 'pitch', 'yaw']) {
        view.sliders[key].value = String(start[key]);
        view.sliders[key].dispatchEvent(new Event('input'));
      }
    });
    controls.append(reset);
    for (const form of ['yaml', 'urdf', 'json']) {
      const button = el('button', { type: 'button', text: 'export ' + form.toUpperCase() });
      button.addEventListener('click', () => {
        const texts = exportTexts(sensor, angles);
        text.value = texts[form];
        const link = el('a', { download: sensor.name + '.' + (form === 'yaml' ? 'yaml' : form === 'urdf' ? 'urdf' : 'json'),
                               href: URL.createObjectURL(new Blob([texts[form]], { type: 'text/plain' })),
                               text: 'download' });
        outputs.querySelectorAll('a').forEach((old) => old.remove());
        outputs.append(link);
      });
      outputs.append(button);
    }
    box.append(outputs, text);
    image.onload = draw;
    draw();
  }

  function cameraSection(parent, sensor) {
    if (!sensor.frames || !sensor.frames.length) return;
    parent.append(el('h3', { text: 'Frames as the estimator saw them' }));
    parent.append(el('p', { class: 'note', text: 'Green: segments through the road\'s vanishing point (red cross); ' +
      'blue: segments that gave the horizon (dashed); yellow: the rest. Undistorted.' }));
    const strip = el('div', { class: 'frames' });
    parent.append(strip);
    for (const frame of sensor.frames) frameFigure(strip, frame);
    adjustmentView(parent, sensor);
  }

  // ---- assembly --------------------------------------------------------------------------------

  function sensorSection(sensor) {
    shiftTimes(sensor);
    currentTimeLabel = sensor.timeLabel;
    const section = el('section', { id: 'sensor-' + sensor.name, class: 'sensor' });
    section.append(el('h2', { text: sensor.name + ' (' + sensor.result.sensor + ')' }));
    root.append(section);
    section.append(resultCard(sensor));
    const evidence = el('div', { class: 'evidence' });
    section.append(evidence);
    let drawn = headingCharts(evidence, sensor);
    const kind = sensor.result.sensor;
    if (kind === 'lidar') drawn = drawn.concat(lidarCharts(evidence, sensor));
    if (kind === 'radar') drawn = drawn.concat(radarCharts(evidence, sensor));
    if (kind === 'camera') drawn = drawn.concat(cameraCharts(evidence, sensor));
    if (!(sensor.result.series || []).length) {
      evidence.append(el('p', { class: 'note', text: 'The result holds no series (written with ' +
        '--without-series, or from x2car eval without --report): no evidence to draw.' }));
    }
    otherCharts(section, sensor, drawn);
    if (kind === 'camera') cameraSection(section, sensor);
    evaluationCharts(section, sensor);
  }

  root.append(el('header', {}, el('h1', { text: 'x2car report: ' + data.title })));
  root.append(el('section', { class: 'overview' }, summaryTable()));
  for (const sensor of data.sensors) sensorSection(sensor);
  root.append(el('footer', {}, el('p', { text: 'Made by: ' + (data.command || 'x2car') }),
    el('p', { text: 'Charts: Apache ECharts ' + echarts.version + ', inlined; this file needs no network.' })));
  window.addEventListener('resize', () => charts.forEach((c) => c.instance.resize()));
})();
