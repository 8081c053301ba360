"""Helpers of the test suite: task generators and the brute-force oracle."""
