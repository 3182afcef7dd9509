"""The painted markings of a standard pitch (metres), drawn by the UI and in recordings alike. They do
not take part in the game: the simulator's own dimensions (pitch, goal) come from WorldConfig."""

CENTRE_CIRCLE_RADIUS = 9.15
PENALTY_AREA = (16.5, 40.32)  # depth from the end line, width
GOAL_AREA = (5.5, 18.32)  # depth from the end line, width
