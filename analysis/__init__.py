"""Exact and asymptotic results for Routh's sphere and the rock'n'roller (no ODE integration here)."""
