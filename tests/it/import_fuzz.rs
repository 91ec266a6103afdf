//! Fuzz tests that check the contract of issue 18 (filled in next).
