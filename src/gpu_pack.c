/* placeholder */ typedef int placeholder_gpu_pack;
