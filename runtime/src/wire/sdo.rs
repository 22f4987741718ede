//! SDO frame layouts (CiA 301 §7.2.4.3): initiate, segment and block messages, and aborts.
