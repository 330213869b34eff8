"""The corpus of hostile and broken inputs (cases.py), shared by the test and the script."""
