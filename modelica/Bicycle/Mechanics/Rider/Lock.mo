within Bicycle.Mechanics.Rider;
model Lock "Holds one generalized speed: replaces the equation of motion of coordinate k of the bodies beyond by J*der(u_k) = 0"
  constant Integer n = 7 "Number of generalized speeds of the system";
  constant Integer k = 7 "Column of the locked speed";
  parameter Bicycle.Units.MomentOfInertia J = 1 "Coefficient of the lock's equation J*der(u_k) = 0 (any positive value gives the same motion)";
  Bicycle.Mechanics.Interfaces.Frame_a frame_a(n = n) "Frame on the side of the ground";
  Bicycle.Mechanics.Interfaces.Frame_b frame_b(n = n) "Same frame on the side of the locked joint and the bodies beyond it";
equation
  frame_b.R = frame_a.R;
  frame_b.r = frame_a.r;
  frame_b.w = frame_a.w;
  frame_b.Wp = frame_a.Wp;
  frame_b.al0 = frame_a.al0;
  frame_b.Vp = frame_a.Vp;
  frame_b.a0 = frame_a.a0;
  frame_b.u = frame_a.u;
  zeros(n) = frame_a.us + frame_b.us;
  frame_b.du = frame_a.du;
  // The generalized force of coordinate k beyond the lock (the joint's equation of motion) is replaced
  for j in 1:n loop
    frame_a.F[j] = if j == k then -J*frame_a.du[k] else -frame_b.F[j];
  end for;
  frame_b.g = frame_a.g;
  0 = frame_a.E + frame_b.E;
  annotation(Documentation(info = "<html><p>Placed between the ground side and a joint whose
coordinate is <code>k</code>: the kinematics and the pairs pass through, except the generalized force
of coordinate <code>k</code>. The sum of the bodies beyond (the joint's equation of motion, which
contains the joint's torque) is dropped and <code>-J*du[k]</code> takes its place, so that Kane's
equation of that speed reads <code>J*der(u_k) = 0</code>. The lock's torque is whatever that takes;
being an internal torque pair of the joint it enters no other equation of motion.</p></html>"));
end Lock;
