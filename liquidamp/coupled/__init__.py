"""Host plus device(s): nonlinear time-domain runs and linear interconnection."""
