"""Lynch & Bustamante, "Precession and recession of the rock'n'roller"."""
