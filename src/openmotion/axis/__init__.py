"""The NC axis: parameters, kernel arrays, drive simulation, state machine and commands."""
