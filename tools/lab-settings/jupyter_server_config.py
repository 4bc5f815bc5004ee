# The Jupyter server settings of `make lab` and `make lab-instructor` (the Makefile passes this file
# with --config). ipykernel warns, in every kernel it starts, "Kernel is running over TCP without
# encryption" unless the server hands it CurveZMQ keys: the kernel's sockets are TCP on 127.0.0.1, and
# jupyter_client provisions keys only when asked to. "auto" asks for them wherever the kernel declares
# it can use them (ipykernel's python3 does), so the kernels' traffic is encrypted and the warning goes.
# A pyzmq built without CurveZMQ would refuse "auto": there the setting is left out (the warning stays).
import zmq

c = get_config()  # noqa: F821 (defined by the Jupyter application that reads this file)
if zmq.has("curve"):
    c.KernelManager.transport_encryption = "auto"
