"""Isaac's utilities: state types (`types`) and rotation conversions (`rotations`)."""
