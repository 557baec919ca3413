"""The built-in planner plugins.  They register through the entry-point group
`symsynth.planners` exactly as a third-party plugin would."""
