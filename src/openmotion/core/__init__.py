"""Units, special input values, enums, error ids and modulo arithmetic: the innermost layer."""
