within Bicycle.Bodies;
model FrontFrame "Front frame H: fork and handlebar, turning about the steer axis (Meijaard 2007, Table 1)"
  extends Bicycle.Bodies.PlanarRigidBody(m = 4, x = 0.9, z = -0.7, Ixx = 0.05892, Ixz = -0.00756, Iyy = 0.06, Izz = 0.00708);
  annotation(Documentation(info = "<html>
<p>Front fork with handlebar (without the front wheel). Defaults: the benchmark bicycle of
Meijaard et al. (2007) (xH, zH, mH, IHxx, IHxz, IHyy, IHzz).</p>
</html>"));
end FrontFrame;
