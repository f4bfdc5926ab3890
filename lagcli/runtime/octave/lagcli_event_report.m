function lagcli_event_report(events, note, state, file)
%LAGCLI_EVENT_REPORT  what happened during a run of lagcli_event_loop, as `lagcli simulate` says it.
%   LAGCLI_EVENT_REPORT(EVENTS, NOTE, STATE) prints one summary line on standard error
%   ("12 events: floor ×12, first at t = 0.4515 s") and NOTE when it is not empty;
%   LAGCLI_EVENT_REPORT(..., FILE) also writes FILE: one CSV row per event, t, event,
%   action, the state before (<name>-) and after (<name>+), impulse (empty but for impacts).
%   STATE: the state names (a cell of char). Shipped with lagcli (lagcli/runtime/octave/).
if isempty(events)
    fprintf(2, '0 events\n');
else
    names = {events.name};
    [order, first] = unique(names, 'first');
    [~, by_time] = sort(first);
    parts = cell(1, numel(order));
    for j = 1:numel(order)
        name = order{by_time(j)};
        parts{j} = sprintf('%s ×%d', name, sum(strcmp(names, name)));
    end
    plural = 's';
    if numel(events) == 1
        plural = '';
    end
    fprintf(2, '%d event%s: %s, first at t = %.10g s\n', numel(events), plural, strjoin(parts, ', '), events(1).t);
end
if ~isempty(note)
    fprintf(2, 'note: %s\n', note);
end
if nargin < 4
    return;
end
fid = fopen(file, 'w');
fprintf(fid, '%s\n', strjoin([{'t', 'event', 'action'}, strcat(state, '-'), strcat(state, '+'), {'impulse'}], ','));
for r = events
    values = sprintf(',%.17g', [r.before, r.after]);
    impulse = '';
    if ~isempty(r.impulse)
        impulse = sprintf('%.17g', r.impulse);
    end
    fprintf(fid, '%.17g,%s,%s%s,%s\n', r.t, r.name, r.action, values, impulse);
end
fclose(fid);
end
