"""Package data: the default caregiver data sets."""
