"""The direct equations of motion of the rock'n'roller, their integration and diagnostics."""
