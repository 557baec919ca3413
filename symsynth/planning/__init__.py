"""From a physical scene to a conditional costmap (issue 4, paper Sec. IV-C).

Planners supply geometry only (`protocol.Planner`); the start-goal and
recursive costmap algorithms are written once over a roadmap and its
per-edge "blocked by" sets (`methods`).
"""
