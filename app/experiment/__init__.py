"""`soccer-lab experiment`: the chapter's SimpleSoccer study (the chapter, 6.2-6.5) — presets, trials run in parallel
(local processes or Ray), resumable trial files, statistics.csv, figures and a report with verdicts."""
