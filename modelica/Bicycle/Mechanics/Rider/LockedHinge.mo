within Bicycle.Mechanics.Rider;
model LockedHinge "Locked hip hinge: the upper body does not accelerate relative to the rear frame (locked at its initial lean angle when started at rest)"
  extends Bicycle.Mechanics.Rider.PartialHinge;
  Bicycle.Mechanics.Rider.Lock lock(n = n, k = k) "Lock of the lean speed";
  Bicycle.Mechanics.Joints.Revolute revolute(n = n, k = k, final nx = 1, final ny = 0, final nz = 0, angle0 = angle0, omega0 = omega0) "Revolute about the longitudinal axis, held by the lock";
equation
  angle = revolute.angle;
  omega = revolute.omega;
  connect(frame_a, lock.frame_a);
  connect(lock.frame_b, revolute.frame_a);
  connect(revolute.frame_b, frame_b);
  annotation(Documentation(info = "<html>
<p>The hinge of <a href=\"modelica://Bicycle.Mechanics.Rider.HipHinge\">HipHinge</a>, locked by
<a href=\"modelica://Bicycle.Mechanics.Rider.Lock\">Lock</a>: the upper body turns relative to the rear
frame by the lean angle as with the free hinge, but the hinge's own equation of motion (Kane's
equation of the lean speed, which contains the hinge torque) is replaced by
<code>der(omega) = 0</code>. Started at rest (<code>omega0 = 0</code>, the default) the upper body keeps
its initial lean angle <code>angle0</code>, and the bicycle moves exactly as one with the upper body
rigidly fixed to the rear frame at that angle. (Started with a lean rate, the hinge keeps that rate,
as if driven.) The rider's lean torque <code>tau_in</code> has no effect.</p>
</html>"));
end LockedHinge;
