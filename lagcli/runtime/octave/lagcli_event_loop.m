function [times_out, states, records, note] = lagcli_event_loop(fun, gfun, act, times, y0, options, model)
%LAGCLI_EVENT_LOOP  integrate with ode45 through events: impacts, resets and stops.
%   [T, Y, RECORDS, NOTE] = LAGCLI_EVENT_LOOP(FUN, GFUN, ACT, TIMES, Y0, OPTIONS, MODEL)
%   integrates y' = FUN(t, y) from TIMES(1) = 0 with ode45 and OPTIONS (RelTol, AbsTol,
%   MaxStep), giving the state at each output time of TIMES (row k of Y at T(k)).
%   GFUN(t, y) -> [value, isterminal, direction] are the event functions (ode45's
%   'Events'); ACT(k, t, y) -> [y_new, impulse, speeds] does event k's action (speeds:
%   the approach speed before and after an impact). MODEL: .names, .actions (cells),
%   .gap, .resting, .budget, .samples (the rules of lagcli/runtime/event_loop_code.py).
%   RECORDS: one struct per event (t, name, action, before, after, impulse); NOTE: why
%   the run ended early ('' when it reached the end).
%
%   ode45 detects each event (its 'Events' option, in the event's direction); the time
%   is then located to the integrator's accuracy: Octave's ode45 places an event by a
%   linear interpolation between the step's ends, so the root of g is found again here
%   with single Dormand-Prince steps (ode45's own formula) from the last accepted step
%   before it, by the Illinois method. The output rows are made the same way (a step
%   from the accepted step before each output time), so a row never mixes the motion
%   before and after an event: a row at exactly t* shows the state after it.
%
%   After an impact, or a reset that leaves g as it was (a kick of velocities g does not
%   use), g counts as exactly 0 where the next segment starts: the event has crossed, and
%   a round-off sign of g at its root cannot fire it again (only an impact's g must then
%   turn back; else its impacts accumulate). A reset's new state is checked against the
%   constraints by ACT (the generated <name>_event_action).
%
%   Shipped with lagcli (lagcli/runtime/octave/); the same text runs in MATLAB.
t_end = times(end);
t0 = times(1);
y = y0(:);
records = struct('t', {}, 'name', {}, 'action', {}, 'before', {}, 'after', {}, 'impulse', {});
note = '';
count = numel(model.names);
last = -Inf(1, count);
fastest = zeros(1, count);
fired = 0;
times_out = zeros(0, 1);
states = zeros(0, numel(y));
options = odeset(options, 'Refine', 1);
quiet = warning('off', 'integrate_adaptive:unexpected_termination');
cleanup = onCleanup(@() warning(quiet));
while true
    if t0 >= t_end
        [times_out, states] = add_rows(times_out, states, times, t0, t0, y, [], [], fun, true);
        return;
    end
    segment = odeset(options, 'Events', @(t, y) segment_events(gfun, t, y, t0, fired));
    [T, Y, TE, ~, IE] = ode45(fun, [t0, t_end], y, segment);
    [k, t_star, y_minus, ja, ended] = next_event(gfun, fun, T, Y, TE, IE, fired, model);
    if k == 0               % no event (a report in the first step is never terminal): ode45 ran to
        [times_out, states] = add_rows(times_out, states, times, t0, t_end, y, T, Y, fun, true);
        return;             % t_end, or to the step budget, which lagcli's simulate reports
    end
    if ended
        note = sprintf(['event ''%s'' recurs at t = %.10g faster than the integrator''s step can ', ...
                        'resolve (accumulation); the run ends there'], model.names{k}, t0);
        [times_out, states] = add_rows(times_out, states, times, t0, t0, y, [], [], fun, true);
        return;
    end
    [times_out, states] = add_rows(times_out, states, times, t0, t_star, y, T(1:ja), Y(1:ja, :), fun, false);
    [y_plus, impulse, speeds] = act(k, t_star, y_minus);
    records(end + 1) = struct('t', t_star, 'name', model.names{k}, 'action', model.actions{k}, ...
                              'before', y_minus.', 'after', y_plus.', 'impulse', impulse); %#ok<AGROW>
    if strcmp(model.actions{k}, 'stop')
        times_out(end + 1, 1) = t_star;
        states(end + 1, :) = y_minus.';
        return;
    end
    note = accumulation(model, k, t_star, t_star - last(k), speeds, fastest(k), numel(records));
    last(k) = t_star;
    if ~isempty(speeds)
        fastest(k) = max(fastest(k), abs(speeds(1)));
    end
    if ~isempty(note)
        times_out(end + 1, 1) = t_star;
        states(end + 1, :) = y_plus.';
        return;
    end
    t0 = t_star;
    y = y_plus;
    fired = k * from_zero(gfun, model, k, t_star, y_minus, y_plus);
end
end

function yes = from_zero(gfun, model, k, t, y_minus, y_plus)
% Does event k's g start the next segment at exactly 0? After an impact (its gap is 0
% there), and after a reset that left g as it was (a kick of velocities g does not use):
% the event has crossed, and a round-off sign of g at its root must not fire it again.
yes = strcmp(model.actions{k}, 'impact');
if strcmp(model.actions{k}, 'reset')
    before = gfun(t, y_minus);
    after = gfun(t, y_plus);
    yes = after(k) == before(k);
end
end

function [k, t_star, y_minus, ja, ended] = next_event(gfun, fun, T, Y, TE, IE, fired, model)
% The first event among ode45's reports (TE, IE) after the accepted steps (T, Y), located
% (k = 0: none; ja: the accepted step before it). FIRED: the event just handled, whose g
% starts at 0: ode45 reports it in the first step wherever g leaves 0, but only a crossing
% counts (the samples of `locate`), so such a report may be no event.
k = 0;
t_star = T(end);
y_minus = [];
ended = false;
for r = 1:numel(IE)
    steps = find(T < TE(r));
    if isempty(steps)
        steps = 1;
    end
    ja = steps(end);
    just = fired * (ja == 1);   % the event just handled matters only in the first step after it
    [k, t_star, y_minus, ended] = locate(gfun, fun, IE(r), T(ja), Y(ja, :).', TE(r), T, just, model);
    if k > 0 || ended
        return;
    end
end
ja = numel(T);
end

function [value, isterminal, direction] = segment_events(gfun, t, y, t0, fired)
% The event functions, with the gap of the impact just handled at exactly 0 where the
% segment starts (the state there may put it a rounding error on the wrong side).
[value, isterminal, direction] = gfun(t, y);
if fired > 0 && t == t0
    value(fired) = 0;
end
end

function note = accumulation(model, k, t, gap, speeds, fastest, total)
% Why the run ends at this event ('' when it goes on): see lagcli/runtime/event_loop_code.py.
note = '';
name = model.names{k};
if ~isempty(speeds) && abs(speeds(2)) <= model.resting * max(fastest, abs(speeds(1)))
    note = sprintf(['event ''%s'' at t = %.10g: separation speed %.3g after the impact (below %g x ', ...
                    'the largest approach speed: the contact has come to rest); the run ends there'], ...
                   name, t, abs(speeds(2)), model.resting);
elseif gap < model.gap * max(1, abs(t))
    note = sprintf(['event ''%s'' recurred after %.3g s at t = %.10g (accumulation: closer than %g x ', ...
                    'max(1, t)); the run ends there'], name, gap, t, model.gap);
elseif total >= model.budget
    note = sprintf('%d events (the budget of one run) by t = %.10g; the run ends there', model.budget, t);
end
end

function [k, t_star, y_star, ended] = locate(gfun, fun, reported, ta, ya, t_guess, T, fired, model)
% The earliest zero crossing, in its event's direction, of any event after the accepted
% step (ta, ya), where ode45 reported event REPORTED near t_guess: (event, time, state
% there); k = 0 when the report is the event just handled (FIRED) leaving 0 in the first
% step without a crossing.
[g_ta, ~, direction] = gfun(ta, ya);
g_ta = g_ta(:).';
if fired > 0
    g_ta(fired) = 0;
end
step = @(t) dp_step(fun, ta, ya, t - ta);
g = @(t) row(gfun(t, step(t)));
later = T(T > ta);
hi = max([t_guess, later(1:min(1, end))]);
if hi <= ta
    hi = ta + max(eps(ta), 1e-12);
end
ended = false;
t_star = ta;
y_star = ya;
while true
    samples = linspace(ta, hi, model.samples + 1);
    before = g_ta;
    for j = 2:numel(samples)
        after = g(samples(j));
        [found, k, t_star, y_star] = earliest(g, step, direction, samples(j - 1), samples(j), before, after);
        if found
            return;
        end
        if j == 2
            second = after;
        end
        before = after;
    end
    if fired == 0 || ~strcmp(model.actions{fired}, 'impact') || direction(fired) == 0 ...
            || second(fired) * direction(fired) < 0
        break;                  % the first sample on the side before a crossing (a reset need not turn back)
    end
    % just after an impact, the first sample is already past a crossing of its gap: the
    % next impact came sooner; look closer, down to the accumulation gap
    if samples(2) - ta < model.gap * max(1, abs(ta))
        k = fired;
        ended = true;
        return;
    end
    hi = samples(2);
end
if reported == fired
    k = 0;                      % ode45 saw g leave 0 where the segment starts: no crossing
    return;
end
% the crossing lies beyond the estimate: widen the window
a = hi;
before = g(a);
for widen = 1:30
    b = ta + 2 * (a - ta);
    after = g(b);
    [found, k, t_star, y_star] = earliest(g, step, direction, a, b, before, after);
    if found
        return;
    end
    a = b;
    before = after;
end
error('lagcli:event', 'event ''%s'': its zero crossing could not be located after t = %.10g', ...
      model.names{reported}, ta);
end

function [found, k, t_star, y_star] = earliest(g, step, direction, a, b, before, after)
% The earliest root in [a, b] among the events whose g crosses there in their direction.
found = false;
k = 0;
t_star = Inf;
y_star = [];
for i = 1:numel(after)
    if crosses(direction(i), before(i), after(i))
        [t, y] = illinois(@(t) pick(g(t), i), step, a, b, before(i), after(i));
        if t < t_star
            found = true;
            k = i;
            t_star = t;
            y_star = y;
        end
    end
end
end

function values = row(values)
values = values(:).';
end

function value = pick(values, k)
value = values(k);
end

function yes = crosses(dir, before, after)
falling = before > 0 && after <= 0;
rising = before < 0 && after >= 0;
if dir < 0
    yes = falling;
elseif dir > 0
    yes = rising;
else
    yes = falling || rising;
end
end

function [t, y] = illinois(g, step, a, b, ga, gb)
% A root of g in [a, b] (g(a), g(b) of opposite signs, or g(b) = 0), to a few ulps of t.
side = 0;
for iteration = 1:200
    if gb == 0 || abs(b - a) <= 4 * eps * max(1, abs(b))
        break;
    end
    c = b - gb * (b - a) / (gb - ga);
    if ~(c > min(a, b) && c < max(a, b))
        c = (a + b) / 2;
    end
    gc = g(c);
    if sign(gc) == sign(gb)
        b = c;
        gb = gc;
        if side == -1
            ga = ga / 2;
        end
        side = -1;
    else
        a = b;
        ga = gb;
        b = c;
        gb = gc;
        side = 1;
    end
end
t = b;
y = step(t);
end

function [times_out, states] = add_rows(times_out, states, times, t0, t1, y0, T, Y, fun, closed)
% The output rows at the times in [t0, t1) ([t0, t1] when CLOSED) from the accepted
% steps (T, Y) (empty: the state y0 at t0 only).
if closed
    wanted = times(times >= t0 & times <= t1);
else
    wanted = times(times >= t0 & times < t1);
end
for tau = wanted(:).'
    if isempty(T)
        y = y0;
    else
        j = find(T <= tau, 1, 'last');
        if T(j) == tau
            y = Y(j, :).';
        else
            y = dp_step(fun, T(j), Y(j, :).', tau - T(j));
        end
    end
    times_out(end + 1, 1) = tau; %#ok<AGROW>
    states(end + 1, :) = y.'; %#ok<AGROW>
end
end

function y = dp_step(fun, t, y0, h)
% One step of size h of the Dormand-Prince 5(4) pair (ode45's formula): y(t + h).
if h == 0
    y = y0;
    return;
end
k1 = fun(t, y0);
k2 = fun(t + h / 5, y0 + h * (k1 / 5));
k3 = fun(t + 3 * h / 10, y0 + h * (3 * k1 / 40 + 9 * k2 / 40));
k4 = fun(t + 4 * h / 5, y0 + h * (44 * k1 / 45 - 56 * k2 / 15 + 32 * k3 / 9));
k5 = fun(t + 8 * h / 9, y0 + h * (19372 * k1 / 6561 - 25360 * k2 / 2187 + 64448 * k3 / 6561 - 212 * k4 / 729));
k6 = fun(t + h, y0 + h * (9017 * k1 / 3168 - 355 * k2 / 33 + 46732 * k3 / 5247 + 49 * k4 / 176 ...
                          - 5103 * k5 / 18656));
y = y0 + h * (35 * k1 / 384 + 500 * k3 / 1113 + 125 * k4 / 192 - 2187 * k5 / 6784 + 11 * k6 / 84);
end
