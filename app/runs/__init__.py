"""Evolution runs: one run played to its folder (run); runs in the background for the app (manager), in a fair
queue for a class (queue) with their games in worker processes or on Ray (games); where evaluations are played
(environments, rcss_cluster); what a run writes (outputs, recording) and the true quality of its best (true_quality)."""
