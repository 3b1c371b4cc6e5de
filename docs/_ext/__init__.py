"""Sphinx helpers of uavcov's documentation site (loaded by docs/conf.py)."""
