"""flexbe_states of omtp-drake flexbe-run: one module per state, as FlexBE's package."""
