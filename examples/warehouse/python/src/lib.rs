//! `warehouse_trustcbr`: the warehouse's catalog as a Python extension module, for
//! trustcbr's Python API (`trustcbr.run(..., catalog=warehouse_trustcbr)`,
//! `trustcbr.Adapter("picking", ..., catalog=warehouse_trustcbr)`, ...). The whole module
//! is the one line below: `trustcbr-python` makes the module of any catalog.

trustcbr_python::catalog_module!(warehouse_trustcbr, warehouse::WarehouseCatalog);
