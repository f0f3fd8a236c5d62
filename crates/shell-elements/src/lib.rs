//! # shell-elements: Belytschko–Tsay family shells and plane-stress J2 plasticity (skeleton; issue 4).
