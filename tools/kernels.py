"""The kernel manager every notebook run of the project uses (`make execute`, the lessons' benchmark):
it hands the kernel CurveZMQ keys where pyzmq has them, as `make lab` does
(tools/lab-settings/jupyter_server_config.py), so ipykernel does not warn "running over TCP without
encryption" at every notebook; else the plain one."""

from __future__ import annotations

from jupyter_client.manager import KernelManager


def kernel_manager() -> KernelManager:
    """A fresh manager for one python3 kernel, with transport encryption where pyzmq supports it."""
    import zmq

    if zmq.has("curve"):
        return KernelManager(kernel_name="python3", transport_encryption="auto")
    return KernelManager(kernel_name="python3")
