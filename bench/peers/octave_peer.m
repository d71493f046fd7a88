% Peer implementation of the clapper model in GNU Octave: ode45 with an
% Events function, the paper's own method (it used Matlab's ODE45).
% Equations (5), (6) in mass-matrix form; rigid impacts with restitution,
% restarting ode45 after each impact; the clapper comes to rest when its
% next flight would be shorter than 1e-7 s and lifts off when the holding
% force changes sign (docs/model.md section 3). Prints one line per stroke:
%   x y style sustained strike_theta_deg strike_phidot_rad_s
% then the time per stroke.
%
%   octave-cli octave_peer.m chart 20 1e-8     % N x N chart, both styles, rtol
%   octave-cli octave_peer.m lab right 1e-8    % the lab bell
1;

function B = make_bell(M, m, a, b, Ib, Ic, r, phimax)
  g = 9.81;
  B = struct('M', M, 'm', m, 'a', a, 'b', b, 'Ib', Ib, 'Ic', Ic, 'r', r, 'phimax', phimax);
  B.j0 = Ib + Ic + m * r^2;
  B.mrb = m * r * b;
  B.gb = (M * a + m * r) * g;
  B.gc = m * b * g;
  B.tb = 2 * pi * sqrt(Ib / (M * a) / g);
end

function B = chart_bell(x, y)
  g = 9.81; tb = 1.8; M = 45.8; m = 1.65; a = 0.24; Ic = 0.20;
  lb = g * tb^2 / (4 * pi^2);
  lc = lb / y;
  B = make_bell(M, m, a, Ic / (m * lc), M * a * lb, Ic, x * lc, 26 * pi / 180);
end

function [tdd, pdd, w11, w12, dt] = accel(B, y)
  sp = sin(y(2)); cp = cos(y(2)); s = sin(y(1) + y(2));
  w11 = B.j0 + 2 * B.mrb * cp;
  w12 = B.Ic + B.mrb * cp;
  f1 = B.mrb * y(4) * (2 * y(3) + y(4)) * sp - B.gb * sin(y(1)) - B.gc * s;
  f2 = -B.mrb * y(3)^2 * sp - B.gc * s;
  dt = w11 * B.Ic - w12^2;
  tdd = (B.Ic * f1 - w12 * f2) / dt;
  pdd = (w11 * f2 - w12 * f1) / dt;
end

function [tdd, q] = resting(B, y)
  sp = sin(y(2)); cp = cos(y(2)); s = sin(y(1) + y(2));
  w11 = B.j0 + 2 * B.mrb * cp;
  w12 = B.Ic + B.mrb * cp;
  tdd = (-B.gb * sin(y(1)) - B.gc * s) / w11;
  q = w12 * tdd + B.mrb * y(3)^2 * sp + B.gc * s;
end

function yn = impact(B, y, e)
  [~, ~, w11, w12, dt] = accel(B, y);
  p = -(1 + e) * y(4) / (w11 / dt);
  yn = [y(1); y(2); y(3) + (-w12 / dt) * p; -e * y(4)];
end

function dy = rhs_fly(t, y, B)
  [tdd, pdd] = accel(B, y);
  dy = [y(3); y(4); tdd; pdd];
end

function dy = rhs_rest(t, y, B)
  [tdd, ~] = resting(B, y);
  dy = [y(3); 0; tdd; 0];
end

% Events: 1 over the top, 2 bottom or turning point, 3 and 4 the stops
% (flying) or 3 lift-off (resting).
function [v, term, dir] = ev(t, y, B, s0, bottom_passed, mode, side)
  if bottom_passed
    v = [-s0 * y(1) - pi; s0 * y(3)]; dir = [1; 1];
  else
    v = [-s0 * y(1) - pi; s0 * y(1)]; dir = [1; -1];
  end
  if mode == 0
    v = [v; y(2) - B.phimax; -y(2) - B.phimax]; dir = [dir; 1; 1];
  else
    [~, q] = resting(B, y);
    v = [v; side * q]; dir = [dir; 1];
  end
  term = ones(size(v));
end

function [first, sustained] = stroke(B, theta0, R, style, rtol)
  s0 = sign(theta0);
  if strcmp(style, 'right') side = s0; else side = -s0; end
  y = [theta0; side * B.phimax; 0; 0];
  t = 0; t_end = 20 * B.tb; e = sqrt(R);
  first = []; sustained = false; bottom_passed = false; struck = false;
  [~, q0] = resting(B, y);
  if side * q0 < 0 mode = 1; rest_side = side; else mode = 0; rest_side = 0; end
  for guard = 1:100000
    opts = odeset('RelTol', rtol, 'AbsTol', rtol, 'Events', @(tt, yy) ev(tt, yy, B, s0, bottom_passed, mode, rest_side));
    if mode == 0
      [tt, yy, te, ye, ie] = ode45(@(tt, yy) rhs_fly(tt, yy, B), [t t_end], y, opts);
    else
      [tt, yy, te, ye, ie] = ode45(@(tt, yy) rhs_rest(tt, yy, B), [t t_end], y, opts);
    end
    if isempty(ie)
      return;
    end
    [t, k] = min(te); which = ie(k); y = ye(k, :)';
    if which == 1
      return;
    elseif which == 2 && ~bottom_passed
      bottom_passed = true;
    elseif which == 2
      if mode == 1 end_side = rest_side; else end_side = sign(y(2) + (y(2) == 0)); end
      if end_side == sign(y(1) + (y(1) == 0)) cont = 'right'; else cont = 'wrong'; end
      sustained = ~isempty(first) && strcmp(cont, style);
      return;
    elseif mode == 1
      mode = 0; rest_side = 0;
    else
      if which == 3 s = 1; else s = -1; end
      if s ~= side && ~struck
        struck = true; first = [y(1) * 180 / pi, y(4)];
      end
      y(2) = s * B.phimax;
      bounced = impact(B, y, e);
      [~, pdd] = accel(B, bounced);
      toward = s * pdd; away = -s * bounced(4);
      stuck = impact(B, y, 0);
      [~, qs] = resting(B, stuck);
      if toward > 0 && 2 * away < 1e-7 * toward && s * qs < 0
        y = stuck; mode = 1; rest_side = s;
      else
        y = bounced;
      end
    end
  end
end

args = argv();
rtol = str2double(args{3});
jobs = {};
if strcmp(args{1}, 'chart')
  n = str2double(args{2});
  xs = linspace(-0.3, 0.7, n); ys = linspace(0.5, 2.5, n);
  for j = 1:n
    for i = 1:n
      jobs{end + 1} = {xs(i), ys(j), 'right'};
      jobs{end + 1} = {xs(i), ys(j), 'wrong'};
    end
  end
else
  jobs{1} = {NaN, NaN, args{2}};
end
tic;
for k = 1:numel(jobs)
  jb = jobs{k};
  if isnan(jb{1})
    B = make_bell(45.8, 1.65, 0.24, 0.25, 4.1, 0.093, 0.10, 26 * pi / 180);
  else
    B = chart_bell(jb{1}, jb{2});
  end
  [first, sus] = stroke(B, 171 * pi / 180, 0.2, jb{3}, rtol);
  if isempty(first) first = [NaN, NaN]; end
  printf('%.6f %.6f %s %d %.9f %.9f\n', jb{1}, jb{2}, jb{3}, sus, first(1), first(2));
end
secs = toc;
printf('strokes %d seconds %.3f per_stroke %.6f\n', numel(jobs), secs, secs / numel(jobs));
