"""`soccer-lab experiment`: the chapter's SimpleSoccer study (spec 6) — presets, trials run in parallel
(local processes or Ray), resumable trial files, statistics.csv, figures and a report with verdicts."""
