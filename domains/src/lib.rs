//! Built-in domain plug-ins for the trust machinery: the paper's movement and patrol
//! scenarios over a 2-D UGV world, with operator models as data.

pub mod spaces;
